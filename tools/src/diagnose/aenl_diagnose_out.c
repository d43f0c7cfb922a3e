/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose_out.c
 * @brief Outputs of the diagnosis: the updated model INI, the figure data (CSV), the JSON object
 *        of `aenl diagnose --json` and the human-readable report.
 */
#define _POSIX_C_SOURCE 200809L

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_diagnose_internal.h"
#include "aenl_tools/aenl_csv.h"
#include "aenl_tools/aenl_json.h"

static const double k_deg = 57.295779513082320876798;

static int is_angular(aenl_sim_dof_t d)
{
    return d != AENL_SIM_DOF_PLUNGE;
}

/* The preload law: a freeplay with inner stiffness 1 has no gap (M = M0 + x). */
static int is_offset(const aenl_sim_law_t *law)
{
    return law->kind == AENL_SIM_LAW_FREEPLAY && fabs(law->inner_stiffness - 1.0) < 1e-12;
}

/* ---- updated INI -------------------------------------------------------------------------------
 */

aenl_status_t aenl_diagnose_write_ini(const aenl_diagnose_result_t *r, const char *source,
                                      const char *path, aenl_err_t *err)
{
    aenl_outfile_t of;
    aenl_status_t st = aenl_outfile_open(&of, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    FILE *fp = of.fp;
    const aenl_sim_model_t *m = &r->updated;
    fprintf(fp, "; Updated model written by `aenl diagnose` (%s).\n", source ? source : "");
    if (r->effect == AENL_DIAGNOSE_NONE)
    {
        fprintf(fp, "; No missing effect was named: this is the baseline under the record's "
                    "conditions.\n");
    }
    else
    {
        fprintf(fp, "; Baseline plus %s in %s. Run it with: aenl simulate updated.ini -o sim.csv\n",
                aenl_diagnose_effect_name(r->effect), aenl_diagnose_dof_name(r->dof));
    }
    fprintf(fp,
            "; Gap (docs/diagnose.md, 'The gap metric'): before %.4g, after %.4g, noise floor "
            "%.4g.\n",
            r->gap_before[r->n_channels], r->gap_after[r->n_channels],
            r->floor_after[r->n_channels]);
    if (r->effect != AENL_DIAGNOSE_NONE)
    {
        const aenl_sim_law_t *l = &m->law[r->dof];
        if (is_angular(r->dof) &&
            (l->kind == AENL_SIM_LAW_FREEPLAY || l->kind == AENL_SIM_LAW_HYSTERESIS))
        {
            fprintf(fp, "; [%s] in degrees: delta %.4g, alpha_f %.4g, preload %.4g%s\n",
                    aenl_diagnose_dof_name(r->dof), l->delta * k_deg, l->x_f * k_deg,
                    l->preload * k_deg,
                    is_offset(l) ? " (inner stiffness 1: no gap, a pure preload M = M0 + x)" : "");
        }
    }
    /* One SNR for every channel (the INI contract): the geometric mean of the record's. */
    aenl_sim_run_t run = r->run;
    run.snr = 0.0;
    run.noise_seed = 1u;
    double ls = 0.0;
    size_t n_ok = 0;
    for (size_t c = 0; c < r->n_channels; ++c)
    {
        if (r->snr[c] > 0.0)
        {
            ls += log(r->snr[c]);
            n_ok++;
        }
    }
    if (n_ok > 0u)
    {
        fprintf(fp, "; the record's measurement noise, SNR per channel:");
        for (size_t c = 0; c < r->n_channels; ++c)
        {
            fprintf(fp, " %s %.3g", r->names[c], r->snr[c]);
        }
        fprintf(fp, " ([noise] holds their geometric mean)\n");
        run.snr = exp(ls / (double)n_ok);
    }
    aenl_sim_write_ini(fp, m, &run);
    return aenl_outfile_commit(&of, err);
}

/* ---- figure data -------------------------------------------------------------------------------
 */

static aenl_status_t write_gaps(const aenl_diagnose_result_t *r, const char *dir, aenl_err_t *err)
{
    char path[4096];
    (void)snprintf(path, sizeof(path), "%s/gaps.csv", dir);
    aenl_outfile_t of;
    aenl_status_t st = aenl_outfile_open(&of, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    fprintf(of.fp, "channel,gap_before,floor_before,gap_after,floor_after");
    for (int f = 0; f < AENL_DIAGNOSE_N_FAMILY; ++f)
    {
        fprintf(of.fp, ",%s_before,%s_after", aenl_diagnose_family_name((aenl_diagnose_family_t)f),
                aenl_diagnose_family_name((aenl_diagnose_family_t)f));
    }
    fprintf(of.fp, "\n");
    for (size_t c = 0; c <= r->n_channels; ++c)
    {
        fprintf(of.fp, "%s,%.6g,%.6g,%.6g,%.6g", c < r->n_channels ? r->names[c] : "total",
                r->gap_before[c], r->floor_before[c], r->gap_after[c], r->floor_after[c]);
        for (int f = 0; f < AENL_DIAGNOSE_N_FAMILY; ++f)
        {
            if (c < r->n_channels)
            {
                fprintf(of.fp, ",%.6g,%.6g", r->fam_before[c][f], r->fam_after[c][f]);
            }
            else
            {
                fprintf(of.fp, ",nan,nan");
            }
        }
        fprintf(of.fp, "\n");
    }
    return aenl_outfile_commit(&of, err);
}

static aenl_status_t write_candidates(const aenl_diagnose_result_t *r, const char *dir,
                                      aenl_err_t *err)
{
    char path[4096];
    (void)snprintf(path, sizeof(path), "%s/candidates.csv", dir);
    aenl_outfile_t of;
    aenl_status_t st = aenl_outfile_open(&of, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    fprintf(of.fp, "effect,dof,n_params,gap,floor,bounded,score,n_evals,refined,delta,alpha_f,"
                   "preload,c3,c5,chosen\n");
    for (size_t i = 0; i < r->n_cand; ++i)
    {
        const aenl_diagnose_cand_t *c = &r->cand[i];
        fprintf(of.fp, "%s,%s,%u,%.6g,%.6g,%.4g,%.6g,%u,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n",
                aenl_diagnose_effect_name(c->effect), aenl_diagnose_dof_name(c->dof), c->n_params,
                c->gap, c->floor, c->bounded, c->score, c->n_evals, c->refined, c->law.delta,
                c->law.x_f, c->law.preload, c->law.n_coeffs >= 3u ? c->law.coeffs[2] : 0.0,
                c->law.n_coeffs >= 5u ? c->law.coeffs[4] : 0.0, i == r->chosen ? 1 : 0);
    }
    return aenl_outfile_commit(&of, err);
}

static aenl_status_t write_curves(const aenl_diagnose_result_t *r, size_t c, const char *dir,
                                  aenl_err_t *err)
{
    static const char *const names[] = {
        "x",        "meas_rise", "meas_rise_lo", "meas_rise_hi", "base_rise",
        "upd_rise", "meas_fall", "meas_fall_lo", "meas_fall_hi", "base_fall",
        "upd_fall", "meas_sd",   "base_sd",      "upd_sd"};
    const size_t nc = sizeof(names) / sizeof(names[0]);
    aenl_table_t t;
    aenl_status_t st = aenl_table_alloc(&t, AENL_DIAGNOSE_N_GRID, nc, names, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const aenl_diagnose_chan_t *ch = &r->chan[c];
    const aenl_diagnose_sig_t *s[3] = {&r->sig_meas[c], &r->sig_base[c], &r->sig_upd[c]};
    const size_t lag = 1; /* the middle lag, period / 8 */
    for (size_t k = 0; k < AENL_DIAGNOSE_N_GRID; ++k)
    {
        const size_t ir = lag * AENL_DIAGNOSE_N_GRID + k;
        const size_t iff = (AENL_DIAGNOSE_N_LAGS + lag) * AENL_DIAGNOSE_N_GRID + k;
        double *d = t.data;
        const size_t nr = t.n_rows;
        d[k] = ch->x_min + (ch->x_max - ch->x_min) * (double)k / (AENL_DIAGNOSE_N_GRID - 1u);
        for (int dir2 = 0; dir2 < 2; ++dir2)
        {
            const size_t i = dir2 ? iff : ir;
            const size_t base = dir2 ? 6u : 1u;
            const double w = s[0]->weight[i];
            const int ok = w >= AENL_DIAGNOSE_MIN_WEIGHT;
            const double se = ok ? 2.0 * s[0]->sd[i] / sqrt(w) : (double)NAN;
            d[base * nr + k] = ok ? s[0]->mean[i] : (double)NAN;
            d[(base + 1u) * nr + k] = ok ? s[0]->mean[i] - se : (double)NAN;
            d[(base + 2u) * nr + k] = ok ? s[0]->mean[i] + se : (double)NAN;
            for (int m = 1; m < 3; ++m)
            {
                const int okm = s[m]->valid && s[m]->weight[i] >= AENL_DIAGNOSE_MIN_WEIGHT;
                d[(base + 2u + (size_t)m) * nr + k] = okm ? s[m]->mean[i] : (double)NAN;
            }
        }
        for (int m = 0; m < 3; ++m)
        {
            const int okm = s[m]->valid && s[m]->weight[ir] >= AENL_DIAGNOSE_MIN_WEIGHT;
            d[(11u + (size_t)m) * nr + k] = okm ? s[m]->sd[ir] : (double)NAN;
        }
    }
    char path[4096];
    (void)snprintf(path, sizeof(path), "%s/curves_%s.csv", dir, r->names[c]);
    st = aenl_table_write(&t, path, err);
    aenl_table_free(&t);
    return st;
}

static aenl_status_t write_spectrum(const aenl_diagnose_result_t *r, size_t c, const char *dir,
                                    aenl_err_t *err)
{
    static const char *const names[] = {"f", "measured", "baseline", "updated"};
    const aenl_diagnose_chan_t *ch = &r->chan[c];
    const size_t nb = ch->seg / 2u;
    aenl_table_t t;
    aenl_status_t st = aenl_table_alloc(&t, nb - 1u, 4, names, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const double *p[3] = {r->psd_meas + c * r->n_bins, r->psd_base + c * r->n_bins,
                          r->psd_upd + c * r->n_bins};
    const int valid[3] = {1, r->sig_base[c].valid, r->sig_upd[c].valid};
    for (size_t k = 1; k < nb; ++k)
    {
        t.data[k - 1u] = (double)k / ((double)ch->seg * r->dt);
        for (size_t m = 0; m < 3u; ++m)
        {
            t.data[(m + 1u) * t.n_rows + k - 1u] = valid[m] ? p[m][k] * r->dt : (double)NAN;
        }
    }
    char path[4096];
    (void)snprintf(path, sizeof(path), "%s/spectrum_%s.csv", dir, r->names[c]);
    st = aenl_table_write(&t, path, err);
    aenl_table_free(&t);
    return st;
}

static aenl_status_t write_timeseries(const aenl_diagnose_result_t *r, const char *dir,
                                      aenl_err_t *err)
{
    const char *names[1 + 3 * AENL_SIM_MAX_Q];
    char buf[3 * AENL_SIM_MAX_Q][40];
    names[0] = "t";
    for (size_t c = 0; c < r->n_channels; ++c)
    {
        static const char *const what[] = {"measured", "baseline", "updated"};
        for (size_t m = 0; m < 3u; ++m)
        {
            (void)snprintf(buf[3u * c + m], sizeof(buf[0]), "%s_%s", r->names[c], what[m]);
            names[1u + 3u * c + m] = buf[3u * c + m];
        }
    }
    /* The last 12 dominant periods (the steady response), at most the whole record. */
    double period = 0.0;
    for (size_t c = 0; c < r->n_channels; ++c)
    {
        period = fmax(period, r->chan[c].period);
    }
    size_t len = (size_t)(12.0 * period);
    len = len < 200u ? 200u : len;
    len = len > r->n_samples ? r->n_samples : len;
    const size_t i0 = r->n_samples - len;
    aenl_table_t t;
    aenl_status_t st = aenl_table_alloc(&t, len, 1u + 3u * r->n_channels, names, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const double *y[3] = {r->y_meas, r->y_base, r->y_upd};
    for (size_t i = 0; i < len; ++i)
    {
        t.data[i] = (double)(i0 + i) * r->dt;
        for (size_t c = 0; c < r->n_channels; ++c)
        {
            for (size_t m = 0; m < 3u; ++m)
            {
                t.data[(1u + 3u * c + m) * len + i] = y[m][c * r->n_samples + i0 + i];
            }
        }
    }
    char path[4096];
    (void)snprintf(path, sizeof(path), "%s/timeseries.csv", dir);
    st = aenl_table_write(&t, path, err);
    aenl_table_free(&t);
    return st;
}

aenl_status_t aenl_diagnose_write_data(const aenl_diagnose_result_t *r, const char *dir,
                                       aenl_err_t *err)
{
    aenl_status_t st = write_gaps(r, dir, err);
    if (st == AENL_OK)
    {
        st = write_candidates(r, dir, err);
    }
    for (size_t c = 0; c < r->n_channels && st == AENL_OK; ++c)
    {
        st = write_curves(r, c, dir, err);
        if (st == AENL_OK)
        {
            st = write_spectrum(r, c, dir, err);
        }
    }
    if (st == AENL_OK)
    {
        st = write_timeseries(r, dir, err);
    }
    return st;
}

/* ---- JSON
 * ---------------------------------------------------------------------------------------- */

/* Values of the named effect's parameters under the contract's keys: v[k] in the order of
 * aenl_diagnose_n_params; for the polynomial the whole coefficient list poly[0..n_poly). */
static void add_values(cJSON *o, aenl_diagnose_effect_t effect, const double *v, const double *poly,
                       size_t n_poly)
{
    static const char *const gap_keys[] = {"delta", "alpha_f", "preload"};
    switch (effect)
    {
        case AENL_DIAGNOSE_FREEPLAY:
        case AENL_DIAGNOSE_HYSTERESIS:
            for (size_t k = 0; k < aenl_diagnose_n_params(effect) && k < AENL_DIAGNOSE_MAX_PAR; ++k)
            {
                (void)cJSON_AddItemToObject(o, gap_keys[k], aenl_json_num(v[k]));
            }
            break;
        case AENL_DIAGNOSE_POLYNOMIAL:
        {
            cJSON *a = cJSON_AddArrayToObject(o, "coeffs");
            for (size_t k = 0; a != NULL && k < n_poly; ++k)
            {
                (void)cJSON_AddItemToArray(a, aenl_json_num(poly[k]));
            }
            break;
        }
        case AENL_DIAGNOSE_PRELOAD:
            (void)cJSON_AddItemToObject(o, "preload", aenl_json_num(v[0]));
            break;
        case AENL_DIAGNOSE_NONE:
        default:
            break;
    }
}

static void add_params(cJSON *params, const aenl_diagnose_result_t *r)
{
    const aenl_sim_law_t *law = &r->updated.law[r->dof];
    double v[AENL_DIAGNOSE_MAX_PAR] = {0.0};
    for (size_t k = 0; k < aenl_diagnose_law_n_params(r->effect, law); ++k)
    {
        v[k] = aenl_diagnose_param_get(law, r->effect, k);
    }
    add_values(params, r->effect, v, law->coeffs, law->n_coeffs);
}

/* The standard errors of the summary fit under the same keys as the parameters (the fixed
 * polynomial coefficients 0). */
static void add_param_sd(cJSON *me, const aenl_diagnose_result_t *r)
{
    if (r->n_param_sd == 0u)
    {
        return;
    }
    cJSON *o = cJSON_AddObjectToObject(me, "params_sd");
    if (o != NULL)
    {
        /* c3, and c5 when the fit had it */
        const double poly[5] = {0.0, 0.0, r->param_sd[0], 0.0,
                                r->n_param_sd > 1u ? r->param_sd[1] : 0.0};
        add_values(o, r->effect, r->param_sd, poly, r->n_param_sd > 1u ? 5u : 3u);
    }
}

/* The DOF of channel c of the result's model (the channel order of the model's outputs). */
static aenl_sim_dof_t channel_dof(const aenl_diagnose_result_t *r, size_t c)
{
    const aenl_sim_dof_t dofs[3] = {AENL_SIM_DOF_PITCH, AENL_SIM_DOF_PLUNGE, AENL_SIM_DOF_FLAP};
    for (size_t k = 0; k < 3u; ++k)
    {
        if (aenl_diagnose_dof_channel(r->updated.type, dofs[k]) == c)
        {
            return dofs[k];
        }
    }
    return AENL_SIM_DOF_PITCH;
}

/* "initial_state": the fitted initial state, its standard errors (INI units, rad for angles)
 * and the samples fitted. */
static void add_initial(cJSON *root, const aenl_diagnose_result_t *r)
{
    cJSON *o = cJSON_AddObjectToObject(root, "initial_state");
    if (o == NULL)
    {
        return;
    }
    (void)cJSON_AddNumberToObject(o, "window", (double)r->initial.window);
    cJSON *v = cJSON_AddObjectToObject(o, "state");
    cJSON *sd = cJSON_AddObjectToObject(o, "sd");
    for (size_t c = 0; v != NULL && sd != NULL && c < r->n_channels; ++c)
    {
        const aenl_sim_dof_t d = channel_dof(r, c);
        char dot[32];
        (void)snprintf(dot, sizeof(dot), "%s_dot", r->names[c]);
        (void)cJSON_AddNumberToObject(v, r->names[c], r->updated.x0[d]);
        (void)cJSON_AddNumberToObject(v, dot, r->updated.v0[d]);
        if (r->initial.window > 0u)
        {
            (void)cJSON_AddNumberToObject(sd, r->names[c], r->initial.x0_sd[d]);
            (void)cJSON_AddNumberToObject(sd, dot, r->initial.v0_sd[d]);
        }
        else /* not fitted: the record's first sample at rest */
        {
            (void)cJSON_AddNullToObject(sd, r->names[c]);
            (void)cJSON_AddNullToObject(sd, dot);
        }
    }
}

char *aenl_diagnose_json(const aenl_diagnose_result_t *r, const char *updated_path)
{
    cJSON *root = cJSON_CreateObject();
    if (root == NULL)
    {
        return NULL;
    }
    (void)cJSON_AddStringToObject(root, "schema", "aenl-diagnose/1");
    (void)cJSON_AddStringToObject(root, "aenl_version", AENL_VERSION);
    cJSON *dis = cJSON_AddArrayToObject(root, "disagreement");
    for (size_t i = 0; dis != NULL && i < r->n_dis; ++i)
    {
        const aenl_diagnose_dis_t *d = &r->dis[i];
        cJSON *o = cJSON_CreateObject();
        (void)cJSON_AddStringToObject(o, "channel", r->names[d->channel]);
        cJSON *band = cJSON_AddArrayToObject(o, "band");
        (void)cJSON_AddItemToArray(band, cJSON_CreateNumber(d->lo));
        (void)cJSON_AddItemToArray(band, cJSON_CreateNumber(d->hi));
        (void)cJSON_AddStringToObject(o, "signature", aenl_diagnose_family_name(d->family));
        (void)cJSON_AddNumberToObject(o, "significance", d->significance);
        (void)cJSON_AddItemToArray(dis, o);
    }
    cJSON *me = cJSON_AddObjectToObject(root, "missing_effect");
    if (me != NULL)
    {
        (void)cJSON_AddStringToObject(me, "type", aenl_diagnose_effect_name(r->effect));
        if (r->effect == AENL_DIAGNOSE_NONE)
        {
            (void)cJSON_AddNullToObject(me, "dof");
        }
        else
        {
            (void)cJSON_AddStringToObject(me, "dof", aenl_diagnose_dof_name(r->dof));
        }
        cJSON *params = cJSON_AddObjectToObject(me, "params");
        if (params != NULL)
        {
            add_params(params, r);
        }
        add_param_sd(me, r);
    }
    if (r->initial.estimated)
    {
        add_initial(root, r);
    }
    (void)cJSON_AddNumberToObject(root, "gap_before", r->gap_before[r->n_channels]);
    (void)cJSON_AddNumberToObject(root, "gap_after", r->gap_after[r->n_channels]);
    if (updated_path != NULL)
    {
        (void)cJSON_AddStringToObject(root, "updated_model", updated_path);
    }
    else
    {
        (void)cJSON_AddNullToObject(root, "updated_model");
    }
    char *s = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    return s;
}

/* ---- report ---------------------------------------------------------------------------------- */

static void print_law(FILE *fp, const aenl_sim_law_t *law, aenl_sim_dof_t d)
{
    const double u = is_angular(d) ? k_deg : 1.0;
    const char *un = is_angular(d) ? " deg" : "";
    switch (law->kind)
    {
        case AENL_SIM_LAW_FREEPLAY:
            if (is_offset(law))
            {
                fprintf(fp, "M0 = %.4g%s", law->preload * u, un);
            }
            else
            {
                fprintf(fp, "delta = %.4g%s, alpha_f = %.4g%s (gap %.4g..%.4g%s)", law->delta * u,
                        un, law->x_f * u, un, law->x_f * u, (law->x_f + law->delta) * u, un);
            }
            break;
        case AENL_SIM_LAW_HYSTERESIS:
            fprintf(fp, "delta = %.4g%s, alpha_f = %.4g%s, M0 = %.4g%s", law->delta * u, un,
                    law->x_f * u, un, law->preload * u, un);
            break;
        case AENL_SIM_LAW_POLYNOMIAL:
            fprintf(fp, "R(x) = x %+.4g x^3", law->n_coeffs >= 3u ? law->coeffs[2] : 0.0);
            if (law->n_coeffs >= 5u)
            {
                fprintf(fp, " %+.4g x^5", law->coeffs[4]);
            }
            break;
        case AENL_SIM_LAW_LINEAR:
        default:
            fprintf(fp, "linear");
            break;
    }
}

/* The standard errors of the named effect's parameters, in the units print_law uses. */
static void print_param_sd(FILE *fp, const aenl_diagnose_result_t *r)
{
    if (r->n_param_sd == 0u)
    {
        return;
    }
    const int ang = is_angular(r->dof) && r->effect != AENL_DIAGNOSE_POLYNOMIAL;
    const double u = ang ? k_deg : 1.0;
    fprintf(fp,
            "\n  standard errors (summary fit, chi2 %.3g for %zu degrees of freedom, %.3g "
            "before):",
            r->chi2, r->chi2_dof, r->chi2_start);
    for (size_t k = 0; k < r->n_param_sd && k < AENL_DIAGNOSE_MAX_PAR; ++k)
    {
        const char *name = aenl_diagnose_param_name(r->effect, k);
        if (isfinite(r->param_sd[k]))
        {
            fprintf(fp, " %s %.3g%s", name, r->param_sd[k] * u, ang ? " deg" : "");
        }
        else
        {
            fprintf(fp, " %s not determined", name);
        }
    }
}

static void print_initial(const aenl_diagnose_result_t *r, FILE *fp)
{
    const aenl_diagnose_initial_t *in = &r->initial;
    if (in->window == 0u)
    {
        fprintf(fp, "\ninitial state: the record's first sample at rest (the baseline cannot be "
                    "fitted to the record's first samples: it runs away there)");
        return;
    }
    fprintf(fp,
            "\ninitial state fitted to the record's first %zu samples (misfit RMS %.3g of the "
            "channels' std), value +- standard error:",
            in->window, in->rms);
    for (size_t c = 0; c < r->n_channels; ++c)
    {
        const aenl_sim_dof_t d = channel_dof(r, c);
        const double u = is_angular(d) ? k_deg : 1.0;
        const char *un = is_angular(d) ? " deg" : "";
        fprintf(fp, "\n  %-6s %.6g +- %.3g%s, rate %.6g +- %.3g%s per time unit", r->names[c],
                r->updated.x0[d] * u, in->x0_sd[d] * u, un, r->updated.v0[d] * u, in->v0_sd[d] * u,
                un);
    }
}

/* The record's channels, the fitted initial state and whether the baseline diverges. */
static void print_record(const aenl_diagnose_result_t *r, FILE *fp)
{
    const size_t nc = r->n_channels;
    fprintf(fp, "record: %zu samples, dt %g; channels:", r->n_samples, r->dt);
    for (size_t c = 0; c < nc; ++c)
    {
        const aenl_diagnose_chan_t *ch = &r->chan[c];
        fprintf(fp,
                " %s (std %.4g, noise %.3g of the record's high-frequency scale %.3g, period "
                "%.4g)",
                r->names[c], ch->scale, ch->noise_sd, ch->noise_record, ch->period * r->dt);
    }
    if (r->initial.estimated)
    {
        print_initial(r, fp);
    }
    for (size_t c = 0; c < nc; ++c)
    {
        if (!r->sig_base[c].valid)
        {
            fprintf(fp,
                    "\nthe baseline diverges under the record's conditions (unstable: it "
                    "flutters); its gap is at the cap %g\n",
                    AENL_DIAGNOSE_CAP);
            break;
        }
    }
}

void aenl_diagnose_report(const aenl_diagnose_result_t *r, FILE *fp)
{
    const size_t nc = r->n_channels;
    print_record(r, fp);
    fprintf(fp, "\n\nwhere they disagree (baseline vs measured, significance = gap / replicate "
                "floor):\n");
    if (r->n_dis == 0u)
    {
        fprintf(fp, "  nothing beyond the noise\n");
    }
    for (size_t i = 0; i < r->n_dis; ++i)
    {
        const aenl_diagnose_dis_t *d = &r->dis[i];
        fprintf(fp, "  %-6s %-17s band [%.4g, %.4g]%s significance %.3g\n", r->names[d->channel],
                aenl_diagnose_family_name(d->family), d->lo, d->hi,
                d->family == AENL_DIAGNOSE_SPECTRUM ? " (frequency)" : "", d->significance);
    }
    fprintf(fp, "\nresponse (measured / baseline / updated): amplitude = half 1..99%% range, "
                "frequency per time unit\n");
    for (size_t c = 0; c < nc; ++c)
    {
        const aenl_diagnose_sig_t *s[3] = {&r->sig_meas[c], &r->sig_base[c], &r->sig_upd[c]};
        fprintf(fp, "  %-6s amplitude", r->names[c]);
        for (int m = 0; m < 3; ++m)
        {
            fprintf(fp, m ? " / %.4g" : " %.4g", s[m]->valid ? s[m]->amp : (double)NAN);
        }
        fprintf(fp, "   frequency");
        for (int m = 0; m < 3; ++m)
        {
            fprintf(fp, m ? " / %.4g" : " %.4g", s[m]->valid ? s[m]->freq / r->dt : (double)NAN);
        }
        fprintf(fp, "\n");
    }
    fprintf(fp,
            "\ncandidates (calibrated by simulation; score = M (gap / common floor)^2 + penalty "
            "x parameters, M = %.4g: from the replicates' spread, over the best fit's "
            "dispersion %.3g):\n",
            r->m_eff, r->dispersion);
    if (r->excitation_shared)
    {
        fprintf(fp,
                "  the record follows the model's own turbulence: its best gap is nearer, in "
                "ratio, to the floor of runs that differ in their noise alone than to that of "
                "runs with other turbulence (baseline's %.3g); the common floor is the former, "
                "%.3g\n",
                r->floor_before[nc], r->common_floor);
    }
    for (size_t i = 0; i < r->n_cand; ++i)
    {
        const aenl_diagnose_cand_t *c = &r->cand[i];
        fprintf(fp, "  %s %-10s %-6s k=%u gap %.4g score %.4g  ", i == r->chosen ? "*" : " ",
                aenl_diagnose_effect_name(c->effect), aenl_diagnose_dof_name(c->dof), c->n_params,
                c->gap, c->score);
        print_law(fp, &c->law, c->dof);
        if (c->bounded < 1.0)
        {
            fprintf(fp, "  (%.0f %% of its runs diverge: the record did not)",
                    100.0 * (1.0 - c->bounded));
        }
        fprintf(fp, "\n");
    }
    fprintf(fp, "\nmissing effect: %s", aenl_diagnose_effect_name(r->effect));
    if (r->effect != AENL_DIAGNOSE_NONE)
    {
        fprintf(fp, " in %s: ", aenl_diagnose_dof_name(r->dof));
        print_law(fp, &r->updated.law[r->dof], r->dof);
        print_param_sd(fp, r);
        if (r->rival < r->n_cand)
        {
            const aenl_diagnose_cand_t *v = &r->cand[r->rival];
            fprintf(fp,
                    "\n  %s: the gap's scores could not tell it from %s in %s (%.4g vs %.4g, "
                    "within one parameter's penalty); refitted to the summaries, that one has "
                    "chi2 %.3g for %zu degrees of freedom%s",
                    r->by_summaries ? "named by the summaries" : "confirmed by the summaries",
                    aenl_diagnose_effect_name(v->effect), aenl_diagnose_dof_name(v->dof),
                    r->cand[r->chosen].score, v->score, r->rival_chi2, r->rival_chi2_dof,
                    r->rival_rejected ? " (rejected)" : "");
        }
        if (r->base_test.n_rep > 0u)
        {
            fprintf(fp,
                    "\n  named although the baseline's gap is within %.3g x its noise floor: the "
                    "summaries of %u simulated records of the baseline reject it (p %.3f)",
                    r->gap_before[nc] / fmax(r->base_floor, AENL_DIAGNOSE_MIN_FLOOR),
                    r->base_test.n_rep, r->base_test.p);
        }
        if (r->summary_rejected)
        {
            fprintf(fp,
                    "\n  the record's summaries reject this model (summary fit chi2 %.3g for %zu "
                    "degrees of freedom, beyond its 99.9 %% point): the parameters are the gap's "
                    "fit, without standard errors",
                    r->chi2, r->chi2_dof);
        }
    }
    else if (!r->explained)
    {
        fprintf(fp, " (the disagreement is significant but no candidate reduces it by 30 %%)");
    }
    else
    {
        fprintf(fp, " (the baseline agrees within %.3g x its noise floor)",
                r->gap_before[nc] / fmax(r->base_floor, AENL_DIAGNOSE_MIN_FLOOR));
        const int agrees = aenl_diagnose_baseline_agrees(r);
        if (r->base_exact)
        {
            fprintf(fp, "\n  the baseline's runs are all alike (no turbulence, no noise) and "
                        "reproduce the record: nothing random is left for its summaries to rank");
        }
        else if (agrees >= 0)
        {
            fprintf(fp,
                    "\n  summaries of the record against %u simulated records of the baseline: "
                    "%s (p %.3f; the record's distance ranked among theirs)",
                    r->base_test.n_rep,
                    agrees ? "they agree"
                           : "they disagree, a small effect the signatures cannot name",
                    r->base_test.p);
        }
    }
    fprintf(fp, "\n\ngap per channel (before -> after; replicate floor before / after):\n");
    for (size_t c = 0; c <= nc; ++c)
    {
        fprintf(fp, "  %-6s %.4g -> %.4g  (floor %.4g / %.4g)\n", c < nc ? r->names[c] : "total",
                r->gap_before[c], r->gap_after[c], r->floor_before[c], r->floor_after[c]);
    }
    fprintf(fp, "\n%u simulations, %.1f s\n", r->n_sims, r->seconds);
}
