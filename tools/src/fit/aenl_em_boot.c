/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_em_boot.c
 * @brief Standard errors of a fit's modes by a parametric bootstrap: records simulated from the
 *        fitted model with its own noise, each fitted again the same way.
 *
 * The bootstrap measures the spread of this estimator (its start, its iterations, its stopping)
 * on records like the one fitted, which an information-matrix formula for the exact maximum
 * would not: EM stops short of the maximum on a weakly excited mode, and the spread of what it
 * returns is what a user reads.
 */

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_tools/aenl_em.h"
#include "aenl_tools/aenl_sort.h"

/* The fit's options for a replicate: the fitted thresholds and order held, no refinement. */
static aenl_em_opts_t replicate_opts(const aenl_em_model_t *m, const aenl_em_opts_t *opts)
{
    aenl_em_opts_t o = *opts;
    o.n_states = m->n_x;
    o.switch_channel = m->switch_channel;
    o.n_thresholds = m->n_modes - 1u;
    for (size_t i = 0; i + 1u < m->n_modes; ++i)
    {
        o.thresholds[i] = m->thresholds[i];
    }
    o.refine = 0;
    o.dt = m->dt;
    return o;
}

/* The pair among the n pairs of e nearest in log frequency to frequency f. */
static size_t nearest_pair(const aenl_em_eig_t *e, size_t n, double f)
{
    size_t best = 0;
    for (size_t j = 1; j < n; ++j)
    {
        if (fabs(log(e[j].frequency / f)) < fabs(log(e[best].frequency / f)))
        {
            best = j;
        }
    }
    return best;
}

/* Median and 1.4826 x median absolute deviation of the finite values among v (n values,
 * reordered); *found receives their number. */
static void robust_spread(double *v, size_t n, double *median, double *sd, size_t *found)
{
    size_t k_fin = 0;
    for (size_t k = 0; k < n; ++k)
    {
        if (isfinite(v[k]))
        {
            v[k_fin++] = v[k];
        }
    }
    *found = k_fin;
    n = k_fin;
    if (n == 0)
    {
        *median = NAN;
        *sd = NAN;
        return;
    }
    aenl_median_mad(v, n, median, sd);
}

/* One replicate: simulate, fit, and add each fitted pair's matched frequency and damping to
 * f_val and z_val (slot (s, i) at offset ((s * half + i) * n_boot + row)). A pair of the fit and
 * one of the refit match when each is the other's nearest in log frequency; a pair without a
 * match (the refit has it overdamped, or two pairs merged) gets NaN, so that its spread is not
 * read off a neighbouring pair. 1 when the replicate counted. */
static int replicate(const aenl_em_result_t *fit, const aenl_em_opts_t *o, size_t n, aenl_rng_t *g,
                     double *y, const aenl_em_eig_t *orig, const size_t *n_osc, size_t n_boot,
                     size_t row, double *f_val, double *z_val)
{
    const aenl_em_model_t *m = &fit->model;
    const size_t half = AENL_EM_MAX_X / 2u;
    aenl_err_t e;
    aenl_err_clear(&e);
    if (aenl_em_simulate_noisy(m, NULL, n, g, y, &e) != AENL_OK)
    {
        return 0;
    }
    aenl_em_result_t r;
    memset(&r, 0, sizeof(r));
    if (aenl_em_fit(y, n, m->n_z, o, &r, &e) != AENL_OK)
    {
        aenl_em_result_free(&r);
        return 0;
    }
    int ok = 1;
    for (size_t s = 0; s < m->n_modes && ok; ++s)
    {
        aenl_em_eig_t eb[AENL_EM_MAX_X];
        size_t ne = 0;
        size_t no = 0;
        ok = aenl_em_modal(&r.model, s, eb, &ne, &no, &e) == AENL_OK;
        const aenl_em_eig_t *os = orig + s * AENL_EM_MAX_X;
        for (size_t i = 0; ok && i < n_osc[s]; ++i)
        {
            const size_t j = no > 0 ? nearest_pair(eb, no, os[i].frequency) : 0;
            const int mutual = no > 0 && nearest_pair(os, n_osc[s], eb[j].frequency) == i;
            f_val[(s * half + i) * n_boot + row] = mutual ? eb[j].frequency : (double)NAN;
            z_val[(s * half + i) * n_boot + row] = mutual ? eb[j].damping : (double)NAN;
        }
    }
    aenl_em_result_free(&r);
    return ok;
}

aenl_status_t aenl_em_bootstrap(const aenl_em_result_t *fit, const aenl_em_opts_t *opts, size_t n,
                                size_t n_boot, uint64_t seed, const aenl_progress_t *progress,
                                aenl_em_boot_t *out, aenl_err_t *err)
{
    if (fit == NULL || opts == NULL || out == NULL || n == 0 || n_boot == 0)
    {
        aenl_err_set(err, "bootstrap: need a fit, its options, n > 0 and replicates > 0");
        return AENL_E_ARG;
    }
    const aenl_em_model_t *m = &fit->model;
    if (m->n_z == 0 || m->n_x == 0 || m->n_modes == 0)
    {
        aenl_err_set(err, "bootstrap: the fit holds no model");
        return AENL_E_ARG;
    }
    if (m->n_u > 0)
    {
        aenl_err_set(err, "bootstrap: the model has known inputs, which it does not simulate");
        return AENL_E_ARG;
    }
    const size_t half = AENL_EM_MAX_X / 2u;
    aenl_em_eig_t orig[AENL_EM_MAX_MODES * AENL_EM_MAX_X];
    size_t n_osc[AENL_EM_MAX_MODES] = {0};
    for (size_t s = 0; s < m->n_modes; ++s)
    {
        size_t ne = 0;
        const aenl_status_t st = aenl_em_modal(m, s, orig + s * AENL_EM_MAX_X, &ne, &n_osc[s], err);
        if (st != AENL_OK)
        {
            return st;
        }
    }
    const size_t slots = m->n_modes * half * n_boot;
    double *f_val = (double *)malloc(slots * sizeof(double));
    double *z_val = (double *)malloc(slots * sizeof(double));
    double *y = (double *)malloc(n * m->n_z * sizeof(double));
    if (f_val == NULL || z_val == NULL || y == NULL)
    {
        free(f_val);
        free(z_val);
        free(y);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    const aenl_em_opts_t o = replicate_opts(m, opts);
    size_t n_ok = 0;
    for (size_t b = 0; b < n_boot; ++b)
    {
        aenl_rng_t g;
        aenl_rng_seed(&g, seed + (uint64_t)b * 0x9E3779B97F4A7C15ull);
        n_ok += (size_t)replicate(fit, &o, n, &g, y, orig, n_osc, n_boot, n_ok, f_val, z_val);
        aenl_progress_report(progress, b + 1u, n_boot);
    }
    memset(out, 0, sizeof(*out));
    out->n_requested = n_boot;
    out->n_ok = n_ok;
    for (size_t s = 0; s < m->n_modes; ++s)
    {
        out->n_pairs[s] = n_osc[s];
        for (size_t i = 0; i < n_osc[s]; ++i)
        {
            double med_f = NAN;
            double med_z = NAN;
            double sd_f = NAN;
            double sd_z = NAN;
            size_t found = 0;
            robust_spread(f_val + (s * half + i) * n_boot, n_ok, &med_f, &sd_f, &found);
            robust_spread(z_val + (s * half + i) * n_boot, n_ok, &med_z, &sd_z, &found);
            out->found[s][i] = found;
            /* a pair that most refits do not reproduce has no standard error to speak of */
            const int spread = found >= 2u && 2u * found > n_ok;
            const aenl_em_eig_t *e = &orig[s * AENL_EM_MAX_X + i];
            out->f_sd[s][i] = spread ? sd_f : (double)NAN;
            out->z_sd[s][i] = spread ? sd_z : (double)NAN;
            out->f_bias[s][i] = spread ? med_f - e->frequency : (double)NAN;
            out->z_bias[s][i] = spread ? med_z - e->damping : (double)NAN;
        }
    }
    free(f_val);
    free(z_val);
    free(y);
    return AENL_OK;
}
