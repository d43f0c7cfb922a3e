/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_curves.c
 * @brief Whole-channel conditional moment curves through the core estimator (host, double).
 */
#include "aenl_tools/aenl_curves.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl/aenl_filter.h"
#include "aenl_tools/aenl_bandwidth.h"
#include "aenl_tools/aenl_mem.h"
#include "aenl_tools/aenl_sort.h"

#define DEFAULT_NODES 64u
#define QUANTILE_LO   0.001

void aenl_curves_opts_default(aenl_curves_opts_t *o)
{ /* prefilter 0 (off) and lags_auto 0 by the memset below */
    memset(o, 0, sizeof(*o));
    o->n_lags = 3;
    o->lags[0] = 1;
    o->lags[1] = 10;
    o->lags[2] = 30;
    o->n_grid = DEFAULT_NODES;
    o->bandwidth = 0.0;
    o->forgetting = 1.0;
    o->split = 1;
    o->cv_max = 200000u;
}

void aenl_curves_free(aenl_curves_t *c)
{
    if (c == NULL)
    {
        return;
    }
    free(c->x);
    free(c->mean);
    free(c->var);
    free(c->n_eff);
    free(c->se);
    free(c->position);
    free(c->velocity);
    free(c->accel);
    free(c->se_position);
    free(c->se_velocity);
    free(c->se_accel);
    memset(c, 0, sizeof(*c));
}

aenl_status_t aenl_curves_parse_lags(const char *s, aenl_curves_opts_t *opts, aenl_err_t *err)
{
    uint16_t n = 0;
    const char *p = s;
    if (s == NULL || *s == '\0')
    {
        aenl_err_set(err, "--lags: empty list (expected e.g. 1,10,30)");
        return AENL_E_ARG;
    }
    while (*p != '\0')
    {
        char *end = NULL;
        errno = 0;
        const long v = strtol(p, &end, 10);
        if (end == p || errno != 0 || (*end != ',' && *end != '\0'))
        {
            aenl_err_set(err, "--lags: '%s' is not a comma-separated list of whole numbers", s);
            return AENL_E_ARG;
        }
        if (v < 1 || v > AENL_MOMENTS_MAX_LAG)
        {
            aenl_err_set(err, "--lags: lag %ld is outside 1..%d (the compile-time maximum)", v,
                         AENL_MOMENTS_MAX_LAG);
            return AENL_E_ARG;
        }
        if (n >= AENL_MOMENTS_MAX_LAGS)
        {
            aenl_err_set(err, "--lags: more than %d lags (the compile-time maximum)",
                         AENL_MOMENTS_MAX_LAGS);
            return AENL_E_ARG;
        }
        for (uint16_t i = 0; i < n; ++i)
        {
            if (opts->lags[i] == (uint16_t)v)
            {
                aenl_err_set(err, "--lags: lag %ld is given twice", v);
                return AENL_E_ARG;
            }
        }
        opts->lags[n++] = (uint16_t)v;
        p = (*end == ',') ? end + 1 : end;
        if (*end == ',' && *p == '\0')
        {
            aenl_err_set(err, "--lags: '%s' ends with a comma", s);
            return AENL_E_ARG;
        }
    }
    opts->n_lags = n;
    return AENL_OK;
}

static aenl_status_t check_opts(const aenl_curves_opts_t *o, aenl_err_t *err)
{
    if (o->n_lags == 0 || o->n_lags > AENL_MOMENTS_MAX_LAGS)
    {
        aenl_err_set(err, "between 1 and %d lags are needed, got %u", AENL_MOMENTS_MAX_LAGS,
                     (unsigned)o->n_lags);
        return AENL_E_ARG;
    }
    for (uint16_t i = 0; i < o->n_lags; ++i)
    {
        if (o->lags[i] < 1 || o->lags[i] > AENL_MOMENTS_MAX_LAG)
        {
            aenl_err_set(err, "lag %u is outside 1..%d", (unsigned)o->lags[i],
                         AENL_MOMENTS_MAX_LAG);
            return AENL_E_ARG;
        }
    }
    if (o->n_grid < 3 || o->n_grid > AENL_MOMENTS_MAX_GRID)
    {
        aenl_err_set(err, "the grid needs 3..%d nodes, got %u", AENL_MOMENTS_MAX_GRID,
                     (unsigned)o->n_grid);
        return AENL_E_ARG;
    }
    if (o->grid_given && (!isfinite(o->x_min) || !isfinite(o->x_max) || !(o->x_max > o->x_min)))
    {
        aenl_err_set(err, "the grid [%g, %g] is not an increasing finite interval", o->x_min,
                     o->x_max);
        return AENL_E_ARG;
    }
    if (!isfinite(o->bandwidth) || o->bandwidth < 0.0)
    {
        aenl_err_set(err, "the bandwidth %g must be positive (or 0 for cross-validation)",
                     o->bandwidth);
        return AENL_E_ARG;
    }
    if (!isfinite(o->forgetting) || !(o->forgetting >= AENL_MOMENTS_MIN_FORGETTING) ||
        o->forgetting > 1.0)
    {
        aenl_err_set(err, "the forgetting factor %g must be in [%g, 1]", o->forgetting,
                     AENL_MOMENTS_MIN_FORGETTING);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

aenl_status_t aenl_curves_period(const double *x, size_t n, double *period, aenl_err_t *err)
{
    double sum = 0.0, sum2 = 0.0;
    size_t n_fin = 0;
    for (size_t i = 0; i < n; ++i)
    {
        if (isfinite(x[i]))
        {
            sum += x[i];
            n_fin++;
        }
    }
    if (n_fin < 4u)
    {
        aenl_err_set(err, "too few finite samples (%zu) to estimate a period", n_fin);
        return AENL_E_ARG;
    }
    const double mean = sum / (double)n_fin;
    for (size_t i = 0; i < n; ++i)
    {
        if (isfinite(x[i]))
        {
            sum2 += (x[i] - mean) * (x[i] - mean);
        }
    }
    const double band = 0.5 * sqrt(sum2 / (double)n_fin);
    /* Count upward passes: below mean - band, then above mean + band. */
    int state = 0; /* -1 below, +1 above, 0 not yet known */
    size_t first = 0, last = 0, n_up = 0;
    for (size_t i = 0; i < n; ++i)
    {
        if (!isfinite(x[i]))
        {
            continue;
        }
        if (x[i] < mean - band)
        {
            state = -1;
        }
        else if (x[i] > mean + band && state == -1)
        {
            state = 1;
            if (n_up == 0u)
            {
                first = i;
            }
            last = i;
            n_up++;
        }
        else if (x[i] > mean + band)
        {
            state = 1;
        }
    }
    if (n_up < 3u)
    {
        aenl_err_set(err,
                     "fewer than two full oscillations: the period (and an automatic pre-filter "
                     "or lag set) cannot be estimated; give --prefilter F and --lags L1,L2,...");
        return AENL_E_ARG;
    }
    *period = (double)(last - first) / (double)(n_up - 1u);
    return AENL_OK;
}

/* Low-pass copy of x (4th-order Butterworth, NaN kept as gaps); NULL when out of memory. The
 * first 4 / cutoff samples are returned as missing: priming assumes a constant input, so a record
 * that starts in motion carries a settling transient that long, which would bias the curves. */
static double *prefiltered(const double *x, size_t n, double cutoff, aenl_err_t *err)
{
    aenl_filter_t f;
    aenl_filter_cfg_t cfg;
    memset(&cfg, 0, sizeof(cfg));
    cfg.cutoff = cutoff;
    cfg.order = 4;
    if (aenl_filter_init(&f, &cfg) != AENL_OK)
    {
        aenl_err_set(err, "pre-filter cutoff %g is outside (0, 0.5) of the sample rate", cutoff);
        return NULL;
    }
    double *y = (double *)aenl_alloc_large(n * sizeof(double));
    if (y == NULL)
    {
        aenl_err_set(err, "out of memory (pre-filtered copy of %zu samples)", n);
        return NULL;
    }
    const size_t settle = (size_t)ceil(4.0 / cutoff);
    for (size_t i = 0; i < n; ++i)
    {
        (void)aenl_filter_push(&f, x[i], &y[i]); /* NaN: passed through as a gap */
        if (i < settle)
        {
            y[i] = (double)NAN;
        }
    }
    return y;
}

/* Geometric lags 1 .. max(5, period / 8): small against the period, as the expansion needs. */
static void auto_lags(double period, aenl_curves_opts_t *o)
{
    double top = period / 8.0;
    top = top < 5.0 ? 5.0 : top;
    top = top > (double)AENL_MOMENTS_MAX_LAG ? (double)AENL_MOMENTS_MAX_LAG : top;
    const unsigned want = 8u;
    uint16_t n = 0;
    for (unsigned i = 0; i < want && n < AENL_MOMENTS_MAX_LAGS; ++i)
    {
        const double v = pow(top, (double)i / (double)(want - 1u));
        const uint16_t lag = (uint16_t)(v + 0.5);
        if (n == 0u || lag > o->lags[n - 1u])
        {
            o->lags[n++] = lag;
        }
    }
    o->n_lags = n;
}

static aenl_status_t curves_compute(const double *x, size_t n, const aenl_curves_opts_t *opts,
                                    aenl_curves_t *out, aenl_err_t *err);

aenl_status_t aenl_curves_compute(const double *x, size_t n, const aenl_curves_opts_t *opts,
                                  aenl_curves_t *out, aenl_err_t *err)
{
    memset(out, 0, sizeof(*out));
    if (!isfinite(opts->prefilter) || opts->prefilter >= 0.5)
    {
        aenl_err_set(err, "the pre-filter cutoff %g must be below 0.5 of the sample rate",
                     opts->prefilter);
        return AENL_E_ARG;
    }
    aenl_curves_opts_t o = *opts;
    double period = 0.0;
    const int need_period = opts->lags_auto || opts->prefilter < 0.0;
    if (need_period)
    {
        const aenl_status_t st = aenl_curves_period(x, n, &period, err);
        if (st != AENL_OK)
        {
            return st;
        }
    }
    if (opts->lags_auto)
    {
        auto_lags(period, &o);
    }
    double cutoff = opts->prefilter;
    if (opts->prefilter < 0.0)
    {
        cutoff = 8.0 / period;
        cutoff = cutoff > 0.4 ? 0.4 : cutoff;
    }
    double *y = NULL;
    if (cutoff > 0.0)
    {
        y = prefiltered(x, n, cutoff, err);
        if (y == NULL)
        {
            return AENL_E_ARG;
        }
    }
    const aenl_status_t st = curves_compute(y ? y : x, n, &o, out, err);
    free(y);
    if (st == AENL_OK)
    {
        out->period = period;
        out->prefilter = cutoff > 0.0 ? cutoff : 0.0;
    }
    return st;
}

/* The finite samples' range: every one and the central 99.8 %, and how many there are. */
typedef struct
{
    size_t n_fin;
    double lo_all, hi_all; /**< the extreme finite samples */
    double lo_q, hi_q;     /**< the QUANTILE_LO and 1 - QUANTILE_LO quantiles */
} curves_range_t;

/* The range of x's finite samples; an error when there is none, the signal is constant or too
 * short for the longest lag. */
static aenl_status_t signal_range(const double *x, size_t n, const aenl_curves_opts_t *opts,
                                  curves_range_t *rg, aenl_err_t *err)
{
    size_t n_fin = 0;
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (size_t i = 0; i < n; ++i)
    {
        if (isfinite(x[i]))
        {
            ++n_fin;
            lo = fmin(lo, x[i]);
            hi = fmax(hi, x[i]);
        }
    }
    if (n_fin == 0)
    {
        aenl_err_set(err, "no finite sample (%zu samples, all missing)", n);
        return AENL_E_ARG;
    }
    uint16_t max_lag = 0;
    for (uint16_t i = 0; i < opts->n_lags; ++i)
    {
        max_lag = opts->lags[i] > max_lag ? opts->lags[i] : max_lag;
    }
    /* selections without a copy, not a sort, which would take a fifth of the whole job on a
     * long record */
    const double p[2] = {QUANTILE_LO, 1.0 - QUANTILE_LO};
    double qv[2] = {0.0, 0.0};
    if (aenl_quantiles_finite(x, n, n_fin, p, 2, qv) != 0)
    {
        aenl_err_set(err, "out of memory (%zu samples)", n_fin);
        return AENL_E_IO;
    }
    rg->n_fin = n_fin;
    rg->lo_all = lo;
    rg->hi_all = hi;
    rg->lo_q = qv[0];
    rg->hi_q = qv[1];
    const double lo_all = rg->lo_all, hi_all = rg->hi_all;
    if (!(hi_all > lo_all) || !(hi_all - lo_all > 1e-12 * (fabs(hi_all) + fabs(lo_all))))
    {
        aenl_err_set(err,
                     "constant signal (every finite sample equals %.17g): no conditional curve",
                     lo_all);
        return AENL_E_ARG;
    }
    if (n_fin < (size_t)max_lag + 3u)
    {
        aenl_err_set(err, "%zu finite samples are too few for lag %u", n_fin, (unsigned)max_lag);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

/* The estimator's configuration: the grid over the quantiles unless given (over the whole range
 * when the quantiles coincide), the bandwidth given or cross-validated (out->bw_method). */
static aenl_status_t estimator_cfg(const double *x, size_t n, const aenl_curves_opts_t *opts,
                                   const curves_range_t *rg, aenl_moments_cfg_t *cfg,
                                   aenl_curves_t *out, aenl_err_t *err)
{
    memset(cfg, 0, sizeof(*cfg));
    cfg->x_min = opts->grid_given ? opts->x_min : rg->lo_q;
    cfg->x_max = opts->grid_given ? opts->x_max : rg->hi_q;
    if (!(cfg->x_max > cfg->x_min))
    {
        cfg->x_min = rg->lo_all;
        cfg->x_max = rg->hi_all;
    }
    cfg->n_grid = opts->n_grid;
    cfg->n_lags = opts->n_lags;
    memcpy(cfg->lags, opts->lags, sizeof(cfg->lags));
    cfg->forgetting = opts->forgetting;
    cfg->direction_split = opts->split ? 1u : 0u;

    out->bw_method = -1;
    if (opts->bandwidth > 0.0)
    {
        cfg->bandwidth = opts->bandwidth;
        return AENL_OK;
    }
    /* The score's memory and time grow with every pair of every lag (64 bytes each): on a long
     * record the first cv_max samples choose the bandwidth, and the kernel regression's
     * MSE-optimal bandwidth, proportional to n^(-1/5), carries it to the whole record. */
    const size_t m = opts->cv_max > 0u && n > opts->cv_max ? opts->cv_max : n;
    aenl_bw_result_t bw;
    const aenl_status_t st = aenl_bw_select(x, m, opts->lags, opts->n_lags, NULL, &bw, err);
    if (st != AENL_OK)
    {
        return st;
    }
    cfg->bandwidth = m < n ? bw.h * pow((double)m / (double)n, 0.2) : bw.h;
    out->bw_method = bw.method;
    out->cv_samples = m;
    return AENL_OK;
}

/* A new estimator of configuration cfg fed every sample of x (*m, the caller frees it). */
static aenl_status_t run_estimator(const double *x, size_t n, const aenl_moments_cfg_t *cfg,
                                   aenl_moments_t **m_out, aenl_err_t *err)
{
    aenl_moments_t *m = malloc(sizeof(*m));
    if (m == NULL)
    {
        aenl_err_set(err, "out of memory (estimator state)");
        return AENL_E_IO;
    }
    const aenl_status_t st = aenl_moments_init(m, cfg);
    if (st != AENL_OK)
    {
        free(m);
        aenl_err_set(err,
                     "estimator rejected the configuration (%s): %u nodes x %u lags%s exceeds the "
                     "capacity of %d cells, or a value is out of range",
                     aenl_status_str(st), (unsigned)cfg->n_grid, (unsigned)cfg->n_lags,
                     cfg->direction_split ? " x 2 directions" : "", AENL_MOMENTS_MAX_CELLS);
        return st == AENL_E_DIM ? AENL_E_DIM : AENL_E_ARG;
    }
    for (size_t i = 0; i < n; ++i)
    {
        (void)aenl_moments_push(m, x[i]); /* NaN: a counted gap, by design */
    }
    *m_out = m;
    return AENL_OK;
}

/* The curves' dimensions and arrays (out->x, mean, var, n_eff, se) for the estimator m. */
static aenl_status_t curves_alloc(const aenl_moments_t *m, const aenl_moments_cfg_t *cfg,
                                  aenl_curves_t *out, aenl_err_t *err)
{
    out->n_lags = cfg->n_lags;
    out->n_grid = cfg->n_grid;
    out->n_dir = cfg->direction_split ? 3u : 1u;
    memcpy(out->lags, cfg->lags, sizeof(out->lags));
    out->bandwidth = cfg->bandwidth;
    out->n_samples = m->n_samples;
    out->n_missing = m->n_missing;
    const size_t total = (size_t)out->n_dir * out->n_lags * out->n_grid;
    if (total == 0) /* aenl_moments_init guarantees n_lags, n_grid >= 1 */
    {
        aenl_err_set(err, "empty configuration (curves)");
        return AENL_E_ARG;
    }
    out->x = malloc(out->n_grid * sizeof(double));
    out->mean = malloc(total * sizeof(double));
    out->var = malloc(total * sizeof(double));
    out->n_eff = malloc(total * sizeof(double));
    out->se = malloc(total * sizeof(double));
    if (out->x == NULL || out->mean == NULL || out->var == NULL || out->n_eff == NULL ||
        out->se == NULL)
    {
        aenl_curves_free(out);
        aenl_err_set(err, "out of memory (curves)");
        return AENL_E_IO;
    }
    return AENL_OK;
}

/* The conditional mean and variance at every direction, lag and node (NaN where the estimator
 * has no answer). */
static void curves_fill(const aenl_moments_t *m, aenl_curves_t *out)
{
    for (uint16_t k = 0; k < out->n_grid; ++k)
    {
        out->x[k] = aenl_moments_node_x(m, k);
    }
    for (int d = 0; d < (int)out->n_dir; ++d)
    {
        for (uint16_t li = 0; li < out->n_lags; ++li)
        {
            for (uint16_t k = 0; k < out->n_grid; ++k)
            {
                aenl_moments_point_t p;
                const size_t at = aenl_curves_at(out, d, li, k);
                if (aenl_moments_query(m, li, k, (aenl_dir_t)d, &p) == AENL_OK)
                {
                    out->mean[at] = p.mean;
                    out->var[at] = p.var;
                    out->n_eff[at] = p.n_eff;
                    out->se[at] = p.se;
                }
                else
                {
                    out->mean[at] = (double)NAN;
                    out->var[at] = (double)NAN;
                    out->n_eff[at] = 0.0;
                    out->se[at] = (double)NAN;
                }
            }
        }
    }
}

/* The lag expansion at node k in direction d into out's expansion arrays (NaN where the
 * estimator has no answer). */
static void expansion_node(const aenl_moments_t *m, uint16_t k, int d, aenl_curves_t *out)
{
    aenl_moments_taylor_t t;
    const size_t at = aenl_curves_node_at(out, d, k);
    if (aenl_moments_taylor(m, k, (aenl_dir_t)d, out->taylor_order, &t) == AENL_OK)
    {
        out->position[at] = t.position;
        out->velocity[at] = t.velocity;
        out->accel[at] = t.accel;
        out->se_position[at] = t.se_position;
        out->se_velocity[at] = t.se_velocity;
        out->se_accel[at] = t.se_accel;
    }
    else
    {
        out->position[at] = (double)NAN;
        out->velocity[at] = (double)NAN;
        out->accel[at] = (double)NAN;
        out->se_position[at] = (double)NAN;
        out->se_velocity[at] = (double)NAN;
        out->se_accel[at] = (double)NAN;
    }
}

/* The lag expansion at every node and direction; it needs at least three lags (none below). */
static aenl_status_t expansion_fill(const aenl_moments_t *m, aenl_curves_t *out, aenl_err_t *err)
{
    if (out->n_lags < 3u)
    {
        return AENL_OK;
    }
    const size_t tot = (size_t)out->n_dir * out->n_grid;
    double **arrs[6] = {&out->position,    &out->velocity,    &out->accel,
                        &out->se_position, &out->se_velocity, &out->se_accel};
    for (size_t a = 0; a < 6u; ++a)
    {
        *arrs[a] = malloc(tot * sizeof(double));
        if (*arrs[a] == NULL)
        {
            aenl_curves_free(out);
            aenl_err_set(err, "out of memory (expansion)");
            return AENL_E_IO;
        }
    }
    out->taylor_order = (uint16_t)(out->n_lags - 1u < AENL_MOMENTS_TAYLOR_MAX_ORDER
                                       ? out->n_lags - 1u
                                       : AENL_MOMENTS_TAYLOR_MAX_ORDER);
    for (int d = 0; d < (int)out->n_dir; ++d)
    {
        for (uint16_t k = 0; k < out->n_grid; ++k)
        {
            expansion_node(m, k, d, out);
        }
    }
    return AENL_OK;
}

static aenl_status_t curves_compute(const double *x, size_t n, const aenl_curves_opts_t *opts,
                                    aenl_curves_t *out, aenl_err_t *err)
{
    memset(out, 0, sizeof(*out));
    aenl_status_t st = check_opts(opts, err);
    curves_range_t rg;
    if (st == AENL_OK)
    {
        st = signal_range(x, n, opts, &rg, err);
    }
    aenl_moments_cfg_t cfg;
    if (st == AENL_OK)
    {
        st = estimator_cfg(x, n, opts, &rg, &cfg, out, err);
    }
    aenl_moments_t *m = NULL;
    if (st == AENL_OK)
    {
        st = run_estimator(x, n, &cfg, &m, err);
    }
    if (st == AENL_OK)
    {
        st = curves_alloc(m, &cfg, out, err);
    }
    if (st == AENL_OK)
    {
        curves_fill(m, out);
        st = expansion_fill(m, out, err);
    }
    free(m);
    return st;
}

aenl_status_t aenl_curves_write_expansion_csv(const aenl_curves_t *c, const char *source,
                                              const char *channel, const char *path,
                                              aenl_err_t *err)
{
    if (c->position == NULL)
    {
        aenl_err_set(err, "the lag expansion needs at least 3 lags (got %u)", (unsigned)c->n_lags);
        return AENL_E_ARG;
    }
    aenl_outfile_t of;
    aenl_status_t st = aenl_outfile_open(&of, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    FILE *fp = of.fp;
    fprintf(fp, "# aenl moments expansion: source=%s channel=%s\n", source, channel);
    fprintf(fp, "# m_L = position + velocity L + accel L^2/2 + ... (order %u, L in samples)\n",
            (unsigned)c->taylor_order);
    fprintf(fp, "# bandwidth=%.17g prefilter=%.17g period=%.17g lags=", c->bandwidth, c->prefilter,
            c->period);
    for (uint16_t i = 0; i < c->n_lags; ++i)
    {
        fprintf(fp, "%s%u", i ? " " : "", (unsigned)c->lags[i]);
    }
    fprintf(fp, "\n# dir: 0 all pairs, 1 rising, 2 falling\n");
    fprintf(fp, "dir,x,position,velocity,accel,se_position,se_velocity,se_accel\n");
    for (int d = 0; d < (int)c->n_dir; ++d)
    {
        for (uint16_t k = 0; k < c->n_grid; ++k)
        {
            const size_t at = aenl_curves_node_at(c, d, k);
            fprintf(fp, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", d, c->x[k],
                    c->position[at], c->velocity[at], c->accel[at], c->se_position[at],
                    c->se_velocity[at], c->se_accel[at]);
        }
    }
    return aenl_outfile_commit(&of, err);
}

static const char *method_name(int method)
{
    return method < 0 ? "given" : aenl_bw_method_str(method);
}

aenl_status_t aenl_curves_write_csv(const aenl_curves_t *c, int dir, const char *source,
                                    const char *channel, const char *path, aenl_err_t *err)
{
    static const char *const dir_names[3] = {"all", "rising", "falling"};
    if (dir < 0 || dir >= (int)c->n_dir)
    {
        aenl_err_set(err, "direction %s needs the direction split",
                     dir_names[dir < 0 ? 0 : dir % 3]);
        return AENL_E_ARG;
    }
    aenl_outfile_t of;
    memset(&of, 0, sizeof(of));
    FILE *fp = stdout;
    const int to_stdout = (path == NULL || strcmp(path, "-") == 0);
    if (!to_stdout)
    {
        const aenl_status_t st = aenl_outfile_open(&of, path, err);
        if (st != AENL_OK)
        {
            return st;
        }
        fp = of.fp;
    }
    fprintf(fp, "# aenl moments: source=%s channel=%s\n", source, channel);
    fprintf(fp, "# bandwidth=%.17g method=%s direction=%s", c->bandwidth, method_name(c->bw_method),
            dir_names[dir]);
    if (c->cv_samples > 0u && c->cv_samples < c->n_samples)
    {
        fprintf(fp, " chosen_on=%zu scaled=(%zu/%zu)^(1/5)", c->cv_samples, c->cv_samples,
                c->n_samples);
    }
    fprintf(fp, "\n");
    fprintf(fp, "# samples=%zu missing=%zu grid=%.17g:%.17g:%u\n", c->n_samples, c->n_missing,
            c->x[0], c->x[c->n_grid - 1u], (unsigned)c->n_grid);
    fprintf(fp, "lag,x,mean,var,n_eff,se\n");
    for (uint16_t li = 0; li < c->n_lags; ++li)
    {
        for (uint16_t k = 0; k < c->n_grid; ++k)
        {
            const size_t at = aenl_curves_at(c, dir, li, k);
            fprintf(fp, "%u,%.17g,%.17g,%.17g,%.17g,%.17g\n", (unsigned)c->lags[li], c->x[k],
                    c->mean[at], c->var[at], c->n_eff[at], c->se[at]);
        }
    }
    if (to_stdout)
    {
        if (fflush(stdout) != 0 || ferror(stdout))
        {
            aenl_err_set(err, "writing to standard output failed");
            return AENL_E_IO;
        }
        return AENL_OK;
    }
    return aenl_outfile_commit(&of, err);
}
