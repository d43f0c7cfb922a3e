/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_identify_out.c
 * @brief The conditional-moments identification's result as JSON (docs/identify.md) and as a
 *        table, with the notes both carry.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "aenl/aenl_classifier.h"
#include "aenl_tools/aenl_bandwidth.h"
#include "aenl_tools/aenl_identify.h"
#include "aenl_tools/aenl_json.h"

/* ---- JSON (docs/identify.md) ----------------------------------------------------------------- */

static cJSON *json_points(const aenl_classifier_result_t *res, int std)
{
    cJSON *a = cJSON_CreateArray();
    if (a == NULL)
    {
        return NULL;
    }
    const unsigned n = res->n_switch <= AENL_CLASSIFIER_MAX_SWITCH ? res->n_switch : 0u;
    for (unsigned k = 0; k < n; ++k)
    {
        const double x = (double)(std ? res->switch_std[k] : res->switch_points[k]);
        if (!cJSON_AddItemToArray(a, aenl_json_num(x)))
        {
            cJSON_Delete(a);
            return NULL;
        }
    }
    return a;
}

/* A polynomial's hardening (true) or softening (false); null for other classes or unknown. */
static cJSON *json_hardening(const aenl_classifier_result_t *res)
{
    return res->cls == AENL_CLASS_POLYNOMIAL && res->hardening != 0
               ? cJSON_CreateBool(res->hardening > 0)
               : cJSON_CreateNull();
}

static cJSON *json_channel(const aenl_identify_channel_t *ch)
{
    cJSON *o = cJSON_CreateObject();
    if (o == NULL)
    {
        return NULL;
    }
    cJSON *lags = cJSON_CreateArray();
    for (uint16_t k = 0; lags != NULL && k < ch->n_lags; ++k)
    {
        if (!cJSON_AddItemToArray(lags, cJSON_CreateNumber((double)ch->lags[k])))
        {
            cJSON_Delete(lags);
            lags = NULL;
        }
    }
    const char *bw_by = ch->bw_method == AENL_BW_CV     ? "cross-validation"
                        : ch->bw_method == AENL_BW_RULE ? "rule"
                                                        : "given";
    const int bad =
        aenl_json_add(o, "name", cJSON_CreateString(ch->name)) != 0 ||
        aenl_json_add(o, "class", cJSON_CreateString(aenl_class_name(ch->res.cls))) != 0 ||
        aenl_json_add(o, "hardening", json_hardening(&ch->res)) != 0 ||
        aenl_json_add(o, "switch_points", json_points(&ch->res, 0)) != 0 ||
        aenl_json_add(o, "switch_point_std", json_points(&ch->res, 1)) != 0 ||
        aenl_json_add(o, "confidence", aenl_json_num((double)ch->res.confidence)) != 0 ||
        aenl_json_add(o, "bandwidth", aenl_json_num(ch->bandwidth)) != 0 ||
        aenl_json_add(o, "bandwidth_by", cJSON_CreateString(bw_by)) != 0 ||
        aenl_json_add(o, "period",
                      ch->period > 0.0 ? aenl_json_num(ch->period) : cJSON_CreateNull()) != 0 ||
        aenl_json_add(o, "noise", aenl_json_num(ch->noise_std)) != 0;
    if (bad)
    {
        cJSON_Delete(lags); /* not attached yet */
        cJSON_Delete(o);
        return NULL;
    }
    if (aenl_json_add(o, "lags", lags) != 0)
    {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

/* The verdict is the model-based test's (not the record's own). */
static int verdict_by_model(const aenl_identify_result_t *r)
{
    return r->model.applied && r->model.explained &&
           (r->model.effect != AENL_DIAGNOSE_NONE || r->model.base_test == 1);
}

/* The notes under the table go to a receiver one line at a time: the table prints them, the
 * JSON's "notes" holds the same lines. */
typedef struct
{
    void (*emit)(void *ctx, const char *line);
    void *ctx;
} notes_t;

static void add_note(const notes_t *nt, const char *fmt, ...) AENL_PRINTF_LIKE(2, 3);

static void add_note(const notes_t *nt, const char *fmt, ...)
{
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(line, sizeof(line), fmt, ap);
    va_end(ap);
    nt->emit(nt->ctx, line);
}

static void notes_of(const aenl_identify_result_t *r, int by_model, const notes_t *nt)
{
    for (size_t i = 0; i < r->n_channels; ++i)
    {
        const aenl_identify_channel_t *ch = &r->ch[i];
        if (ch->bw_method == AENL_BW_RULE)
        {
            add_note(nt, "%s: bandwidth by the rule of thumb (cross-validation gave no minimum)",
                     ch->name);
        }
        if (ch->n_missing > 0)
        {
            add_note(nt, "%s: %zu missing sample%s (NaN cells) skipped", ch->name, ch->n_missing,
                     ch->n_missing == 1 ? "" : "s");
        }
        if (ch->dither_std > ch->noise_std) /* not a mere top-up of a noisy record */
        {
            add_note(nt,
                     "%s: cleaner than the regression's noise floor (SNR 10); white noise of std "
                     "%.3g dithered in for it",
                     ch->name, ch->dither_std);
        }
        if (ch->explained_by >= 0)
        {
            add_note(nt,
                     "%s: the law it shows is explained by that of %s (its force reaches %s "
                     "through the coupling); %s taken as linear",
                     ch->name, r->ch[ch->explained_by].name, ch->name, ch->name);
        }
    }
    if (r->impulses > 0)
    {
        add_note(nt,
                 "impulsive excitation: %zu event%s (%zu rows) left out of the restoring-force "
                 "regression",
                 r->impulses, r->impulses == 1 ? "" : "s", r->impulse_rows);
    }
    if (r->limit_cycle >= 0)
    {
        add_note(nt,
                 "limit cycle: sustained oscillation of constant amplitude in %s (kurtosis %.2f); "
                 "a linear structure has none",
                 r->ch[r->limit_cycle].name, r->ch[r->limit_cycle].kurtosis);
        if (r->verdict >= 0 && !by_model)
        {
            add_note(nt, "one orbit does not tell polynomial, freeplay and hysteresis apart: the "
                         "class is a guess among the three (confidence 1/3 for the class)");
        }
    }
}

/* The verdict is the pipeline's (aenl_identify_result_t: verdict, verdict_class,
 * verdict_confidence). */
static void json_note(void *ctx, const char *line)
{
    cJSON *a = (cJSON *)ctx;
    cJSON *x = a != NULL ? cJSON_CreateString(line) : NULL;
    if (x != NULL && !cJSON_AddItemToArray(a, x))
    {
        cJSON_Delete(x);
    }
}

/* The model-based test (--model) as an object: what the table's model lines say. */
static cJSON *json_model(const aenl_identify_result_t *r, const char *model)
{
    const aenl_identify_model_t *m = &r->model;
    cJSON *o = cJSON_CreateObject();
    cJSON *alone = cJSON_CreateObject();
    if (o == NULL || alone == NULL)
    {
        cJSON_Delete(o);
        cJSON_Delete(alone);
        return NULL;
    }
    const int second = m->effect2 != AENL_DIAGNOSE_NONE;
    int bad = aenl_json_add(o, "file", cJSON_CreateString(model));
    bad |= aenl_json_add(o, "explained", cJSON_CreateBool(m->explained));
    bad |= aenl_json_add(o, "effect", cJSON_CreateString(aenl_diagnose_effect_name(m->effect)));
    bad |= aenl_json_add(o, "dof",
                         m->effect != AENL_DIAGNOSE_NONE
                             ? cJSON_CreateString(aenl_diagnose_dof_name(m->dof))
                             : cJSON_CreateNull());
    bad |= aenl_json_add(o, "gap_before", aenl_json_num(m->gap_before));
    bad |= aenl_json_add(o, "gap_after", aenl_json_num(m->gap_after));
    bad |= aenl_json_add(o, "effect2",
                         second ? cJSON_CreateString(aenl_diagnose_effect_name(m->effect2))
                                : cJSON_CreateNull());
    bad |= aenl_json_add(o, "dof2",
                         second ? cJSON_CreateString(aenl_diagnose_dof_name(m->dof2))
                                : cJSON_CreateNull());
    bad |=
        aenl_json_add(o, "gap_after2", second ? aenl_json_num(m->gap_after2) : cJSON_CreateNull());
    bad |= aenl_json_add(o, "baseline_summaries_p",
                         m->base_test >= 0 && m->base_sum.n_rep > 0u ? aenl_json_num(m->base_sum.p)
                                                                     : cJSON_CreateNull());
    bad |= aenl_json_add(o, "diagnoses", cJSON_CreateNumber((double)m->n_diagnoses));
    bad |= aenl_json_add(alone, "class", cJSON_CreateString(aenl_class_name(m->data_class)));
    bad |= aenl_json_add(alone, "channel",
                         m->data_verdict >= 0 ? cJSON_CreateString(r->ch[m->data_verdict].name)
                                              : cJSON_CreateNull());
    bad |= aenl_json_add(alone, "confidence", aenl_json_num(m->data_confidence));
    bad |= aenl_json_add(o, "record_alone", alone);
    if (bad)
    {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

aenl_status_t aenl_identify_print_json(FILE *out, const aenl_identify_result_t *r, const char *path,
                                       size_t rows, const char *model)
{
    cJSON *root = cJSON_CreateObject();
    cJSON *verdict = cJSON_CreateObject();
    cJSON *chans = cJSON_CreateArray();
    cJSON *notes = cJSON_CreateArray();
    const int by_model = verdict_by_model(r);
    int bad = (root == NULL);
    if (verdict != NULL)
    {
        static const aenl_classifier_result_t k_none; /* no switching points */
        const aenl_classifier_result_t *res = r->verdict >= 0 ? &r->ch[r->verdict].res : &k_none;
        bad |=
            aenl_json_add(verdict, "class", cJSON_CreateString(aenl_class_name(r->verdict_class)));
        bad |= aenl_json_add(verdict, "channel",
                             r->verdict >= 0 ? cJSON_CreateString(r->ch[r->verdict].name)
                                             : cJSON_CreateNull());
        bad |= aenl_json_add(verdict, "hardening", json_hardening(res));
        bad |= aenl_json_add(verdict, "switch_points", json_points(res, 0));
        bad |= aenl_json_add(verdict, "confidence", aenl_json_num(r->verdict_confidence));
        bad |= aenl_json_add(verdict, "by_model", cJSON_CreateBool(by_model));
        /* one orbit of a limit cycle: the class is one of three alike */
        bad |= aenl_json_add(verdict, "guess",
                             cJSON_CreateBool(r->limit_cycle >= 0 && r->verdict >= 0 && !by_model));
    }
    const notes_t nt = {json_note, notes};
    notes_of(r, by_model, &nt);
    for (size_t i = 0; chans != NULL && i < r->n_channels; ++i)
    {
        cJSON *c = json_channel(&r->ch[i]);
        if (c == NULL || !cJSON_AddItemToArray(chans, c))
        {
            cJSON_Delete(c);
            bad = 1;
            break;
        }
    }
    if (root != NULL)
    {
        bad |= aenl_json_add(root, "schema", cJSON_CreateString("aenl-identify/2"));
        bad |= aenl_json_add(root, "aenl_version", cJSON_CreateString(AENL_VERSION));
        bad |= aenl_json_add(root, "file", cJSON_CreateString(path));
        bad |= aenl_json_add(root, "rows", cJSON_CreateNumber((double)rows));
        bad |= aenl_json_add(root, "verdict", verdict);
        bad |= aenl_json_add(root, "channels", chans);
        bad |= aenl_json_add(root, "impulses", cJSON_CreateNumber((double)r->impulses));
        bad |= aenl_json_add(root, "limit_cycle",
                             r->limit_cycle >= 0 ? cJSON_CreateString(r->ch[r->limit_cycle].name)
                                                 : cJSON_CreateNull());
        bad |= aenl_json_add(root, "model",
                             r->model.applied ? json_model(r, model != NULL ? model : "")
                                              : cJSON_CreateNull());
        bad |= aenl_json_add(root, "notes", notes);
    }
    else
    {
        cJSON_Delete(verdict);
        cJSON_Delete(chans);
        cJSON_Delete(notes);
    }
    char *text = bad ? NULL : cJSON_Print(root);
    cJSON_Delete(root);
    if (text == NULL)
    {
        return AENL_E_DIM;
    }
    fprintf(out, "%s\n", text);
    free(text);
    return AENL_OK;
}

/* ---- the table ------------------------------------------------------------------------------- */

const char *aenl_identify_class_label(const aenl_classifier_result_t *res)
{
    if (res->cls == AENL_CLASS_POLYNOMIAL)
    {
        return res->hardening > 0   ? "polynomial (hardening)"
               : res->hardening < 0 ? "polynomial (softening)"
                                    : "polynomial";
    }
    return aenl_class_name(res->cls);
}

/* "1..12 (6)" or "1,2,4" for a short list. */
static void lags_label(const aenl_identify_channel_t *ch, char *buf, size_t n)
{
    buf[0] = '\0';
    if (ch->n_lags == 0)
    {
        (void)snprintf(buf, n, "-");
    }
    else if (ch->n_lags <= 3)
    {
        size_t len = 0;
        for (uint16_t k = 0; k < ch->n_lags && len < n; ++k)
        {
            const int w = snprintf(buf + len, n - len, "%s%u", k ? "," : "", (unsigned)ch->lags[k]);
            len += (w > 0) ? (size_t)w : 0u;
        }
    }
    else
    {
        (void)snprintf(buf, n, "%u..%u (%u)", (unsigned)ch->lags[0],
                       (unsigned)ch->lags[ch->n_lags - 1u], (unsigned)ch->n_lags);
    }
}

static void print_points(FILE *out, const aenl_classifier_result_t *res, int with_std)
{
    if (res->n_switch == 0 || res->n_switch > AENL_CLASSIFIER_MAX_SWITCH)
    {
        fprintf(out, "-");
        return;
    }
    for (unsigned k = 0; k < res->n_switch; ++k)
    {
        fprintf(out, "%s%.5g", k ? ", " : "", (double)res->switch_points[k]);
        if (with_std && isfinite((double)res->switch_std[k]))
        {
            fprintf(out, " ± %.2g", (double)res->switch_std[k]);
        }
        else if (with_std)
        {
            fprintf(out, " (no std)"); /* the summary fit rejected the model: no standard error */
        }
    }
}

/* The lines of the model-based test (--model). */
static void print_model(FILE *out, const aenl_identify_result_t *r, const char *model)
{
    const aenl_identify_model_t *m = &r->model;
    fprintf(out, "  model-based test against %s (as aenl diagnose): ", model);
    if (!m->explained)
    {
        fprintf(out,
                "the baseline misses the record (gap %.3g) and no candidate effect explains it; "
                "the verdict is the record's own\n",
                m->gap_before);
        return;
    }
    if (m->effect == AENL_DIAGNOSE_NONE && m->base_test == 1 && m->base_sum.n_rep == 0u)
    {
        fprintf(out,
                "the baseline reproduces the record (gap %.3g; its runs are all alike, without "
                "turbulence or noise): no missing effect\n",
                m->gap_before);
    }
    else if (m->effect == AENL_DIAGNOSE_NONE && m->base_test == 1)
    {
        fprintf(out,
                "the baseline fits the record (gap %.3g, within twice its noise floor), and its "
                "summaries agree (p %.2f): no missing effect\n",
                m->gap_before, m->base_sum.p);
    }
    else if (m->effect == AENL_DIAGNOSE_NONE && m->base_test == 0)
    {
        fprintf(out,
                "the baseline fits the record by the gap (%.3g, within twice its noise floor) but "
                "not by its summaries (p %.2f): a small effect the test cannot name; the verdict "
                "is the record's own\n",
                m->gap_before, m->base_sum.p);
    }
    else if (m->effect == AENL_DIAGNOSE_NONE)
    {
        fprintf(out,
                "the baseline fits the record (gap %.3g, within twice its noise floor): no "
                "evidence either way, the verdict is the record's own\n",
                m->gap_before);
    }
    else
    {
        fprintf(out, "%s in %s, gap %.3g -> %.3g%s\n", aenl_diagnose_effect_name(m->effect),
                aenl_diagnose_dof_name(m->dof), m->gap_before, m->gap_after,
                m->effect == AENL_DIAGNOSE_PRELOAD
                    ? " (a constant moment: the stiffness keeps its slope, so linear)"
                    : "");
        if (m->effect2 != AENL_DIAGNOSE_NONE)
        {
            fprintf(out,
                    "  and a second effect, with the first in the model: %s in %s; each refitted "
                    "with the other in place, gap -> %.3g\n",
                    aenl_diagnose_effect_name(m->effect2), aenl_diagnose_dof_name(m->dof2),
                    m->gap_after2);
        }
    }
    fprintf(out, "  the record alone: ");
    if (m->data_verdict >= 0)
    {
        fprintf(out, "%s in channel %s (confidence %.3f)\n", aenl_class_name(m->data_class),
                r->ch[m->data_verdict].name, m->data_confidence);
    }
    else
    {
        fprintf(out, "%s (confidence %.3f)\n", aenl_class_name(m->data_class), m->data_confidence);
    }
}

static void print_note(void *ctx, const char *line)
{
    fprintf((FILE *)ctx, "  %s\n", line);
}

void aenl_identify_print_table(FILE *out, const aenl_identify_result_t *r, const char *path,
                               size_t rows, const aenl_identify_opts_t *o, const char *model)
{
    const int by_model = verdict_by_model(r);
    int w_name = 7;
    for (size_t i = 0; i < r->n_channels; ++i)
    {
        const int len = (int)strlen(r->ch[i].name);
        w_name = len > w_name ? (len < 40 ? len : 40) : w_name;
    }
    fprintf(out, "%s: %zu rows, %zu channel%s; bandwidth %s, pre-filter %s\n", path, rows,
            r->n_channels, r->n_channels == 1 ? "" : "s",
            o->bandwidth > 0.0 ? "given" : "by cross-validation", o->prefilter ? "on" : "off");
    fprintf(out, "%-*s  %-22s  %10s  %10s  %-10s  %8s  %10s  %s\n", w_name, "channel", "class",
            "confidence", "bandwidth", "lags", "period", "noise", "switching points (± std)");
    for (size_t i = 0; i < r->n_channels; ++i)
    {
        const aenl_identify_channel_t *ch = &r->ch[i];
        char lags[64];
        lags_label(ch, lags, sizeof(lags));
        fprintf(out, "%-*s  %-22s  %10.3f  %10.4g  %-10s  %8.4g  %10.3g  ", w_name, ch->name,
                aenl_identify_class_label(&ch->res), (double)ch->res.confidence, ch->bandwidth,
                lags, ch->period, ch->noise_std);
        print_points(out, &ch->res, 1);
        fprintf(out, "\n");
    }
    const notes_t nt = {print_note, out};
    notes_of(r, by_model, &nt);
    fprintf(out, "  (bandwidth and noise in channel units, period in samples, lags in samples)\n");
    if (r->model.applied)
    {
        print_model(out, r, model);
    }
    const char *vlabel = by_model ? "verdict (model-based)" : "verdict";
    if (r->verdict >= 0)
    {
        const aenl_identify_channel_t *ch = &r->ch[r->verdict];
        fprintf(out, "%s: %s in channel %s (confidence %.3f", vlabel,
                aenl_identify_class_label(&ch->res), ch->name, r->verdict_confidence);
        if (r->verdict_share > 0.0 && r->verdict_share < 1.0)
        {
            fprintf(out, " = %.3f for the class in %s × %.3f for the channel",
                    r->verdict_confidence / r->verdict_share, ch->name, r->verdict_share);
        }
        fprintf(out, ")");
        if (ch->res.n_switch > 0)
        {
            fprintf(out, ", switching points ");
            print_points(out, &ch->res, 0);
        }
        fprintf(out, "\n");
    }
    else if (r->verdict_class == AENL_CLASS_LINEAR)
    {
        fprintf(out, "%s: linear, no channel shows a nonlinearity (confidence %.3f)\n", vlabel,
                r->verdict_confidence);
    }
    else
    {
        fprintf(out, "verdict: insufficient data, no channel could be decided\n");
    }
}
