/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_identify.c
 * @brief The identify pipeline (see aenl_identify.h).
 */
#include "aenl_tools/aenl_identify.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "aenl_tools/aenl_bandwidth.h"
#include "aenl_tools/aenl_csv.h"
#include "aenl_tools/aenl_impulse.h"
#include "aenl_tools/aenl_rfs.h"
#include "aenl_tools/aenl_rng.h"

/** Classification lags at most (geometric from 1 to period / 8). */
#define ID_MAX_LAGS 8
/** Butterworth order of the pre-filter. */
#define ID_FILTER_ORDER 4
/** Pre-filter cutoff in cycles of the dominant period: 8 / period (harmonics up to the 7th). */
#define ID_CUTOFF_CYCLES 8.0
/** Grid nodes at most (one per bandwidth). */
#define ID_MAX_GRID 120
/** Longest lag: period / ID_LAG_DIV (the expansion must stay local in time). */
#define ID_LAG_DIV 8.0
/** Order of the lag expansion: cubic in the lag (position, velocity, acceleration, jerk). */
#define ID_TAYLOR_ORDER 3u
/** Grid nodes at least. */
#define ID_MIN_GRID 60
/** Restoring-force regression: common pre-filter cutoff in cycles of the shortest dominant
 *  period (every channel through the same filter keeps the coupling linear). */
#define ID_RFS_CUTOFF_CYCLES 5.0
/** Restoring-force regression: consecutive position lags from 2. */
#define ID_RFS_DENSE_LAGS 8u
/** Impulse screening threshold, robust standard deviations (aenl_impulse.h). */
#define ID_IMPULSE_Z 3.0
/** An impulse must at least double the energy of the motion over the longest period. */
#define ID_IMPULSE_GAIN 2.0
/** Periods at which the autocorrelation tells a sustained (limit-cycle) oscillation. */
#define ID_SUSTAINED_PERIODS 10.0
/** Kurtosis below which a sustained oscillation has a constant amplitude: a sinusoid has 1.5, a
 *  Gaussian process 3, and a sinusoid plus a Gaussian part with a third of the variance 7/3. */
#define ID_LIMIT_CYCLE_KURTOSIS (7.0 / 3.0)
/** Restoring-force regression: tents per direction. */
#define ID_RFS_NODES 32u
/** The regression's noise floor, a fraction of each channel's standard deviation (SNR 10). A
 *  record cleaner than that is dithered up to it (white Gaussian noise, a fixed seed: the same
 *  record gives the same answer) before the regression's pre-filter. On a noise-free record the
 *  dense lags interpolate the second difference (a finite difference of the past is a linear
 *  regressor), and what they leave is deterministic and the same from block to block, so the
 *  blocks' t is no test of anything: laws are missed and spurious ones pass. */
#define ID_RFS_NOISE_FLOOR 0.1
#define ID_RFS_DITHER_SEED 0x5eed0d17u

/* ---- sources ----------------------------------------------------------------------------- */

static aenl_status_t arrays_open(void *ctx, aenl_err_t *err)
{
    (void)err;
    ((aenl_identify_arrays_t *)ctx)->row = 0;
    return AENL_OK;
}

static int arrays_next(void *ctx, double *row, aenl_err_t *err)
{
    (void)err;
    aenl_identify_arrays_t *a = ctx;
    if (a->row >= a->n_rows)
    {
        return 0;
    }
    for (size_t c = 0; c < a->n_cols; ++c)
    {
        row[c] = a->cols[c][a->row];
    }
    a->row++;
    return 1;
}

static void arrays_close(void *ctx)
{
    (void)ctx;
}

void aenl_identify_arrays_source(aenl_identify_source_t *src, aenl_identify_arrays_t *ctx,
                                 const double *const *cols, const char *const *names, size_t n_cols,
                                 size_t n_rows)
{
    memset(src, 0, sizeof(*src));
    ctx->cols = cols;
    ctx->n_cols = n_cols;
    ctx->n_rows = n_rows;
    ctx->row = 0;
    src->n_cols = n_cols;
    src->names = names;
    src->ctx = ctx;
    src->open = arrays_open;
    src->next = arrays_next;
    src->close = arrays_close;
}

/* CSV: the channels are the columns that are not the time column (aenl_csv_is_time_column). */

static aenl_status_t csv_src_open(void *ctx, aenl_err_t *err)
{
    aenl_identify_csv_t *c = ctx;
    aenl_csv_t *csv = NULL;
    const aenl_status_t st = aenl_csv_open(&csv, c->path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    c->csv = csv;
    return AENL_OK;
}

static int csv_src_next(void *ctx, double *row, aenl_err_t *err)
{
    aenl_identify_csv_t *c = ctx;
    const int r = aenl_csv_next(c->csv, c->row, err);
    if (r <= 0)
    {
        return r < 0 ? -1 : 0;
    }
    for (size_t k = 0; k < c->n_cols; ++k)
    {
        row[k] = c->row[c->col[k]];
    }
    return 1;
}

static void csv_src_close(void *ctx)
{
    aenl_identify_csv_t *c = ctx;
    aenl_csv_close(c->csv);
    c->csv = NULL;
}

void aenl_identify_csv_free(aenl_identify_csv_t *ctx)
{
    if (ctx == NULL)
    {
        return;
    }
    if (ctx->csv != NULL)
    {
        aenl_csv_close(ctx->csv);
    }
    if (ctx->names != NULL)
    {
        for (size_t k = 0; k < ctx->n_cols; ++k)
        {
            free(ctx->names[k]);
        }
        free(ctx->names);
    }
    free(ctx->col);
    free(ctx->row);
    memset(ctx, 0, sizeof(*ctx));
}

aenl_status_t aenl_identify_csv_source(aenl_identify_source_t *src, aenl_identify_csv_t *ctx,
                                       const char *path, const char *time_column, aenl_err_t *err)
{
    memset(src, 0, sizeof(*src));
    memset(ctx, 0, sizeof(*ctx));
    /* The pipeline reads the record more than once (the bandwidth, then the curves): a pipe or
     * a terminal would give the second pass nothing, or the rest of the stream. */
    struct stat sb;
    if (path != NULL && stat(path, &sb) == 0 && !S_ISREG(sb.st_mode))
    {
        aenl_err_set(err,
                     "%s: not a regular file: identify reads the record more than once, so save "
                     "the stream to a file first (or use --method test, which reads it once)",
                     path);
        return AENL_E_ARG;
    }
    aenl_csv_t *csv = NULL;
    aenl_status_t st = aenl_csv_open(&csv, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const size_t n_file = aenl_csv_n_cols(csv);
    size_t n_ch = 0;
    for (size_t k = 0; k < n_file; ++k)
    {
        n_ch += !aenl_csv_is_time_column(aenl_csv_col_name(csv, k), time_column);
    }
    if (time_column != NULL && n_ch == n_file)
    {
        aenl_err_set(err, "%s: no column named '%s' for the time", path, time_column);
        aenl_csv_close(csv);
        return AENL_E_ARG;
    }
    if (n_ch == 0)
    {
        aenl_err_set(err, "%s: no data column (only time)", path);
        aenl_csv_close(csv);
        return AENL_E_ARG;
    }
    ctx->path = path;
    ctx->n_cols = n_ch;
    ctx->names = calloc(n_ch, sizeof(char *));
    ctx->col = calloc(n_ch, sizeof(size_t));
    ctx->row = calloc(n_file + 1, sizeof(double));
    if (ctx->names == NULL || ctx->col == NULL || ctx->row == NULL)
    {
        aenl_csv_close(csv);
        aenl_identify_csv_free(ctx);
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    st = AENL_OK;
    for (size_t k = 0, j = 0; k < n_file; ++k)
    {
        const char *name = aenl_csv_col_name(csv, k);
        if (aenl_csv_is_time_column(name, time_column))
        {
            continue;
        }
        ctx->col[j] = k;
        ctx->names[j] = malloc(strlen(name) + 1);
        if (ctx->names[j] == NULL)
        {
            st = AENL_E_IO;
            break;
        }
        memcpy(ctx->names[j], name, strlen(name) + 1);
        j++;
    }
    aenl_csv_close(csv);
    if (st != AENL_OK)
    {
        aenl_identify_csv_free(ctx);
        aenl_err_set(err, "out of memory");
        return st;
    }
    src->n_cols = n_ch;
    src->names = (const char *const *)ctx->names;
    src->ctx = ctx;
    src->open = csv_src_open;
    src->next = csv_src_next;
    src->close = csv_src_close;
    return AENL_OK;
}

/* ---- options ----------------------------------------------------------------------------- */

void aenl_identify_opts_default(aenl_identify_opts_t *o)
{
    memset(o, 0, sizeof(*o));
    o->bandwidth = 0.0;
    o->prefilter = 1;
    o->cv_max = 20000;
    o->channel = -1;
}

/* ---- per-channel work -------------------------------------------------------------------- */

typedef struct id_chan
{
    /* pass 1 */
    size_t n, n_missing, n_block;
    double mean, m2, lo, hi;
    double *block; /**< the first cv_max samples (NaN kept) */
    /* set-up */
    double cutoff;
    size_t settle;
    aenl_filter_t filter;
    aenl_moments_t *mom, *disp;
    size_t pushed;
    /* pass 2: central power sums of the pre-filtered signal about the pass-1 mean */
    double n2, s2, s4;
} id_chan_t;

/**
 * Dominant period from the autocorrelation of the block: white measurement noise only touches
 * lag 0, so the first maximum after the first zero crossing is the period even at SNR 2. 0 when
 * the autocorrelation never turns (no oscillation in the block).
 */
/* Variance of the block's finite samples about `mean`; *n0 their count. */
static double block_var(const double *x, size_t n, double mean, size_t *n0)
{
    double r0 = 0.0;
    *n0 = 0;
    for (size_t i = 0; i < n; ++i)
    {
        if (isfinite(x[i]))
        {
            r0 += (x[i] - mean) * (x[i] - mean);
            (*n0)++;
        }
    }
    return *n0 > 0 ? r0 / (double)*n0 : 0.0;
}

/* Autocorrelation of the block at `lag`, normalised by the variance r0 (> 0), over the pairs of
 * finite samples. */
static double block_acf(const double *x, size_t n, double mean, size_t lag, double r0)
{
    double s = 0.0;
    size_t k = 0;
    for (size_t i = 0; i + lag < n; ++i)
    {
        if (isfinite(x[i]) && isfinite(x[i + lag]))
        {
            s += (x[i] - mean) * (x[i + lag] - mean);
            k++;
        }
    }
    return k > 0 ? s / (double)k / r0 : 0.0;
}

/* Autocorrelation at `lag` (0 when the block is shorter than two lags or constant). */
static double acf_at(const double *x, size_t n, double mean, size_t lag)
{
    size_t n0;
    const double r0 = block_var(x, n, mean, &n0);
    return (lag < n / 2u && r0 > 0.0) ? block_acf(x, n, mean, lag, r0) : 0.0;
}

static double acf_period(const double *x, size_t n, double mean)
{
    const size_t max_lag = n / 3u;
    size_t n0;
    const double r0 = block_var(x, n, mean, &n0);
    if (n0 < 16u || !(r0 > 0.0))
    {
        return 0.0;
    }
    double prev2 = 1.0, prev = 1.0;
    int crossed = 0;
    for (size_t lag = 1; lag <= max_lag; ++lag)
    {
        const double r = block_acf(x, n, mean, lag, r0);
        if (r < 0.0)
        {
            crossed = 1;
        }
        else if (crossed && lag >= 3u && prev >= prev2 && prev > r && prev > 0.0)
        {
            /* parabola through lags - 2, - 1, lag around the peak at lag - 1 */
            const double den = prev2 - 2.0 * prev + r;
            const double off = den < 0.0 ? 0.5 * (prev2 - r) / den : 0.0;
            return (double)(lag - 1u) + (fabs(off) < 1.0 ? off : 0.0);
        }
        prev2 = prev;
        prev = r;
    }
    return 0.0;
}

/**
 * Geometric lags 2 .. top (distinct integers, at most ID_MAX_LAGS, at least 3). Lag 1 is left out:
 * the direction split compares X_c with X_{c-1}, and the backward series of lag 1 would read the
 * very sample that decided the direction (its noise is biased by the decision).
 */
static uint16_t make_lags(double top, uint16_t *lags)
{
    if (top < 4.0)
    {
        top = 4.0;
    }
    if (top > (double)AENL_MOMENTS_MAX_LAG)
    {
        top = (double)AENL_MOMENTS_MAX_LAG;
    }
    uint16_t n = 0;
    for (int k = 0; k < ID_MAX_LAGS; ++k)
    {
        const double v = 2.0 * pow(top / 2.0, (double)k / (ID_MAX_LAGS - 1));
        const uint16_t l = (uint16_t)lround(v);
        if (n == 0u || l > lags[n - 1u])
        {
            lags[n++] = l;
        }
    }
    return n;
}

/** Differences estimate of white noise: min over k of Var(diff^k x) / C(2k, k). */
static double noise_level(const double *x, size_t n)
{
    static const double k_binom[5] = {1.0, 2.0, 6.0, 20.0, 70.0};
    double best = INFINITY;
    for (int k = 1; k <= 4; ++k)
    {
        double s = 0.0, s2 = 0.0;
        size_t m = 0;
        for (size_t i = (size_t)k; i < n; ++i)
        {
            double d = 0.0, c = 1.0;
            int ok = 1;
            for (int j = 0; j <= k; ++j) /* sum_j (-1)^j C(k, j) x[i - j] */
            {
                const double v = x[i - (size_t)j];
                ok = ok && isfinite(v);
                d += ((j % 2) ? -c : c) * v;
                c = c * (double)(k - j) / (double)(j + 1);
            }
            if (ok)
            {
                s += d;
                s2 += d * d;
                m++;
            }
        }
        if (m > 1u)
        {
            const double var = (s2 - s * s / (double)m) / (double)(m - 1u);
            const double v = var / k_binom[k];
            best = v < best ? v : best;
        }
    }
    return isfinite(best) ? sqrt(best) : 0.0;
}

static void chan_free(id_chan_t *c)
{
    free(c->block);
    free(c->mom);
    free(c->disp);
    memset(c, 0, sizeof(*c));
}

void aenl_identify_free(aenl_identify_result_t *r)
{
    if (r == NULL)
    {
        return;
    }
    for (size_t k = 0; k < r->n_channels && r->ch != NULL; ++k)
    {
        aenl_identify_channel_t *c = &r->ch[k];
        free(c->x);
        free(c->mean);
        free(c->var);
        free(c->position);
        free(c->accel);
    }
    free(r->ch);
    memset(r, 0, sizeof(*r));
}

/** Pass over the source calling fn(ctx, row) for every row. */
typedef aenl_status_t (*row_fn_t)(void *ctx, const double *row, aenl_err_t *err);

static aenl_status_t for_rows(const aenl_identify_source_t *src, double *row, row_fn_t fn,
                              void *ctx, aenl_err_t *err)
{
    aenl_status_t st = src->open(src->ctx, err);
    if (st != AENL_OK)
    {
        return st;
    }
    for (;;)
    {
        const int r = src->next(src->ctx, row, err);
        if (r < 0)
        {
            st = AENL_E_ARG;
            break;
        }
        if (r == 0)
        {
            break;
        }
        st = fn(ctx, row, err);
        if (st != AENL_OK)
        {
            break;
        }
    }
    src->close(src->ctx);
    return st;
}

typedef struct id_run
{
    const aenl_identify_source_t *src;
    const aenl_identify_opts_t *opts;
    size_t n_ch;
    size_t *col; /**< source column of each analysed channel */
    id_chan_t *ch;
    /* restoring-force regression over every analysed channel at once */
    aenl_rfs_t *rfs;
    aenl_rfs_cfg_t rfs_cfg;
    aenl_filter_cfg_t rfs_fc;
    double rfs_period;         /**< the longest period, samples */
    aenl_filter_t *rfs_filter; /**< n_ch, one common design */
    double *rfs_row;
    size_t rfs_settle, rfs_pushed;
    /* impulse screening (rfs_screen): the free-law model's residuals, the screen and the
     * regression accumulated again with the events left out */
    double *rfs_res, *rfs_kept;
    aenl_impulse_t *imp;
    aenl_rfs_t *rfs_again;
    aenl_rng_t rfs_rng;                 /**< the dither, seeded again at every pass */
    double rfs_dither[AENL_RFS_MAX_CH]; /**< its standard deviation per channel (input units) */
} id_run_t;

static aenl_status_t pass1_row(void *ctx, const double *row, aenl_err_t *err)
{
    id_run_t *run = ctx;
    for (size_t k = 0; k < run->n_ch; ++k)
    {
        id_chan_t *c = &run->ch[k];
        const double x = row[run->col[k]];
        if (c->n_block < run->opts->cv_max)
        {
            c->block[c->n_block++] = x;
        }
        if (!isfinite(x))
        {
            c->n_missing++;
            continue;
        }
        if (fabs(x) > 1e120)
        {
            aenl_err_set(err, "channel %s: value %g is beyond any physical range",
                         run->src->names[run->col[k]], x);
            return AENL_E_ARG;
        }
        c->n++;
        const double d = x - c->mean;
        c->mean += d / (double)c->n;
        c->m2 += d * (x - c->mean);
        c->lo = (c->n == 1u || x < c->lo) ? x : c->lo;
        c->hi = (c->n == 1u || x > c->hi) ? x : c->hi;
    }
    return AENL_OK;
}

/* The regression's pre-filter over one dithered data row into run->rfs_row (NaN while it
 * settles). A deviate is drawn for every cell, missing or not, so every pass adds the same. */
static void rfs_filter_row(id_run_t *run, const double *row)
{
    for (size_t k = 0; k < run->n_ch; ++k)
    {
        double y = row[run->col[k]];
        const double e = aenl_rng_gauss(&run->rfs_rng);
        y += isfinite(y) ? run->rfs_dither[k] * e : 0.0;
        (void)aenl_filter_push(&run->rfs_filter[k], y, &y);
        run->rfs_row[k] = run->rfs_pushed < run->rfs_settle ? (double)NAN : y;
    }
    run->rfs_pushed++;
}

static aenl_status_t pass2_row(void *ctx, const double *row, aenl_err_t *err)
{
    (void)err;
    id_run_t *run = ctx;
    for (size_t k = 0; k < run->n_ch; ++k)
    {
        id_chan_t *c = &run->ch[k];
        double y = row[run->col[k]];
        if (c->cutoff > 0.0)
        {
            (void)aenl_filter_push(&c->filter, y, &y); /* NaN passes as a gap */
            if (c->pushed < c->settle)
            {
                y = (double)NAN; /* the filter's start-up transient is not data */
            }
        }
        c->pushed++;
        if (isfinite(y))
        {
            const double d2 = (y - c->mean) * (y - c->mean);
            c->n2 += 1.0;
            c->s2 += d2;
            c->s4 += d2 * d2;
        }
        (void)aenl_moments_push(c->mom, y); /* NaN: a missing sample, alignment kept */
        (void)aenl_moments_push(c->disp, y);
    }
    if (run->rfs != NULL)
    {
        rfs_filter_row(run, row);
        aenl_rfs_push(run->rfs, run->rfs_row);
    }
    return AENL_OK;
}

/* A row the screen held back into the regression accumulated again; one left out goes in as a
 * gap, so that no regression row has it in its window: the lagged positions stand for the
 * state only along free motion, and an impulse breaks that for every lag across it. */
static void rfs_push_kept(id_run_t *run, int left_out)
{
    for (size_t k = 0; left_out && k < run->n_ch; ++k)
    {
        run->rfs_kept[k] = (double)NAN;
    }
    aenl_rfs_push(run->rfs_again, run->rfs_kept);
}

/* Pass 3 (the screen's scan) and pass 4 (the regression again, events left out). */
static aenl_status_t screen_row(void *ctx, const double *row, aenl_err_t *err)
{
    (void)err;
    id_run_t *run = ctx;
    rfs_filter_row(run, row);
    aenl_rfs_residual(run->rfs, run->rfs_row, run->rfs_res);
    if (run->rfs_again == NULL)
    {
        aenl_impulse_scan(run->imp, run->rfs_res);
    }
    else
    {
        int out = 0;
        if (aenl_impulse_step(run->imp, run->rfs_res, run->rfs_row, run->rfs_kept, &out))
        {
            rfs_push_kept(run, out);
        }
    }
    return AENL_OK;
}

/* The channel's pass-1 description: sample counts, noise, dominant period and how sustained the
 * oscillation is; an error for a channel with fewer than two finite samples or a constant one. */
static aenl_status_t chan_describe(const id_chan_t *c, const char *name,
                                   aenl_identify_channel_t *out, aenl_err_t *err)
{
    if (c->n < 2u)
    {
        aenl_err_set(err, "channel %s: no finite samples", name);
        return AENL_E_ARG;
    }
    const double sd = sqrt(c->m2 / (double)(c->n - 1u));
    if (!(sd > 0.0) || !(c->hi > c->lo))
    {
        aenl_err_set(err, "channel %s: constant signal (%g): nothing to identify", name, c->lo);
        return AENL_E_ARG;
    }
    out->name = name;
    out->n_samples = c->n;
    out->n_missing = c->n_missing;
    out->noise_std = noise_level(c->block, c->n_block);
    out->period = acf_period(c->block, c->n_block, c->mean);
    out->sustained = out->period > 0.0
                         ? acf_at(c->block, c->n_block, c->mean,
                                  (size_t)floor(ID_SUSTAINED_PERIODS * out->period + 0.5))
                         : 0.0;
    out->bw_method = -1;
    return AENL_OK;
}

/* The pre-filter at ID_CUTOFF_CYCLES / period (none without a period, or when that is not below
 * 0.4 of the sample rate), and the samples its start-up transient spoils. */
static aenl_status_t chan_prefilter(id_chan_t *c, const char *name,
                                    const aenl_identify_opts_t *opts, aenl_identify_channel_t *out,
                                    aenl_err_t *err)
{
    c->cutoff = 0.0;
    if (opts->prefilter && out->period > 0.0)
    {
        const double fc = ID_CUTOFF_CYCLES / out->period;
        if (fc < 0.4)
        {
            c->cutoff = fc;
        }
    }
    if (c->cutoff > 0.0)
    {
        aenl_filter_cfg_t fcfg = {(aenl_real_t)c->cutoff, ID_FILTER_ORDER};
        if (aenl_filter_init(&c->filter, &fcfg) != AENL_OK)
        {
            aenl_err_set(err, "channel %s: pre-filter design failed (cutoff %g)", name, c->cutoff);
            return AENL_E_NUMERIC;
        }
        c->settle = (size_t)ceil(4.0 / c->cutoff);
    }
    out->prefilter = c->cutoff;
    return AENL_OK;
}

/* The classification lags (from the period, or up to 16 without one); an error when the
 * channel is too short for the longest of them. */
static aenl_status_t chan_lags(const id_chan_t *c, const char *name, aenl_identify_channel_t *out,
                               aenl_err_t *err)
{
    out->n_lags = make_lags(out->period > 0.0 ? out->period / ID_LAG_DIV : 16.0, out->lags);
    const size_t need = (size_t)out->lags[out->n_lags - 1u] + c->settle + 64u;
    if (c->n < need)
    {
        aenl_err_set(err,
                     "channel %s: %zu finite samples are too few (at least %zu for lags up to %u)",
                     name, c->n, need, (unsigned)out->lags[out->n_lags - 1u]);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

/* The block filtered as pass 2 will filter it (*y, the caller frees it; NaN while the filter
 * settles) and its finite range [*lo, *hi]: they give the range and the bandwidth. */
static aenl_status_t chan_filtered_block(const id_chan_t *c, const char *name, double **y_out,
                                         double *lo_out, double *hi_out, aenl_err_t *err)
{
    double *y = malloc((c->n_block > 0 ? c->n_block : 1u) * sizeof(double));
    if (y == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    aenl_filter_t f = c->filter;
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < c->n_block; ++i)
    {
        double v = c->block[i];
        if (c->cutoff > 0.0)
        {
            (void)aenl_filter_push(&f, v, &v);
            v = (i < c->settle) ? (double)NAN : v;
        }
        y[i] = v;
        if (isfinite(v))
        {
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
    }
    if (!(hi > lo))
    {
        free(y);
        aenl_err_set(err, "channel %s: constant signal after the pre-filter's start-up", name);
        return AENL_E_ARG;
    }
    *y_out = y;
    *lo_out = lo;
    *hi_out = hi;
    return AENL_OK;
}

/* The kernel bandwidth: the one given, else cross-validated on the filtered block y and kept
 * within one node per bandwidth over `range` for ID_MIN_GRID .. ID_MAX_GRID nodes. */
static aenl_status_t chan_bandwidth(const id_chan_t *c, const double *y, double range,
                                    const aenl_identify_opts_t *opts, aenl_identify_channel_t *out,
                                    aenl_err_t *err)
{
    double h = opts->bandwidth;
    if (h > 0.0)
    {
        out->bw_method = -1;
    }
    else
    {
        aenl_bw_result_t bw;
        const aenl_status_t st =
            aenl_bw_select(y, c->n_block, out->lags, out->n_lags, NULL, &bw, err);
        if (st != AENL_OK)
        {
            return st;
        }
        h = bw.h;
        out->bw_method = bw.method;
        /* one node per bandwidth, ID_MIN_GRID .. ID_MAX_GRID nodes */
        h = h < range / (ID_MAX_GRID - 2) ? range / (ID_MAX_GRID - 2) : h;
        h = h > range / (ID_MIN_GRID - 2) ? range / (ID_MIN_GRID - 2) : h;
    }
    out->bandwidth = h;
    return AENL_OK;
}

/* The classification moments (symmetric lags, both directions) on the grid [lo - h, hi + h] of
 * spacing h, and the display moments (the paper's forward lags 1, 10, 30 that the record is
 * long enough for) on the same grid. */
static aenl_status_t chan_moments(id_chan_t *c, const char *name, double lo, double hi,
                                  aenl_identify_channel_t *out, aenl_err_t *err)
{
    const double h = out->bandwidth;
    double n_nodes = floor((hi - lo) / h) + 3.0;
    if (n_nodes > (double)AENL_CLASSIFIER_MAX_NODES)
    {
        n_nodes = (double)AENL_CLASSIFIER_MAX_NODES;
    }
    out->n_grid = (uint16_t)n_nodes;
    out->x_min = lo - h;
    out->x_max = hi + h;
    aenl_moments_cfg_t mc;
    memset(&mc, 0, sizeof(mc));
    mc.x_min = out->x_min;
    mc.x_max = out->x_max;
    mc.n_grid = out->n_grid;
    mc.bandwidth = h;
    mc.n_lags = out->n_lags;
    memcpy(mc.lags, out->lags, sizeof(mc.lags));
    mc.forgetting = 1.0;
    mc.direction_split = 1;
    mc.symmetric = 1;
    c->mom = malloc(sizeof(*c->mom));
    c->disp = malloc(sizeof(*c->disp));
    if (c->mom == NULL || c->disp == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    if (aenl_moments_init(c->mom, &mc) != AENL_OK)
    {
        aenl_err_set(err, "channel %s: moments configuration rejected (grid %u, h %g)", name,
                     (unsigned)mc.n_grid, h);
        return AENL_E_ARG;
    }
    static const uint16_t k_disp[AENL_IDENTIFY_DISPLAY_LAGS] = {1, 10, 30};
    out->n_display = 0;
    for (int k = 0; k < AENL_IDENTIFY_DISPLAY_LAGS; ++k)
    {
        if ((size_t)k_disp[k] * 4u < c->n)
        {
            out->display_lags[out->n_display++] = k_disp[k];
        }
    }
    mc.n_lags = out->n_display;
    mc.symmetric = 0; /* the paper's curves: forward lags */
    memset(mc.lags, 0, sizeof(mc.lags));
    memcpy(mc.lags, out->display_lags, sizeof(out->display_lags));
    if (aenl_moments_init(c->disp, &mc) != AENL_OK)
    {
        aenl_err_set(err, "channel %s: display moments configuration rejected", name);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

/**
 * Set up one channel after pass 1: period, pre-filter, lags, range, bandwidth, grid, moments.
 */
static aenl_status_t chan_setup(id_chan_t *c, const char *name, const aenl_identify_opts_t *opts,
                                aenl_identify_channel_t *out, aenl_err_t *err)
{
    aenl_status_t st = chan_describe(c, name, out, err);
    if (st == AENL_OK)
    {
        st = chan_prefilter(c, name, opts, out, err);
    }
    if (st == AENL_OK)
    {
        st = chan_lags(c, name, out, err);
    }
    double *y = NULL, lo = 0.0, hi = 0.0;
    if (st == AENL_OK)
    {
        st = chan_filtered_block(c, name, &y, &lo, &hi, err);
    }
    if (st != AENL_OK)
    {
        return st;
    }
    /* The grid covers the whole record (pass 1's raw range less three noise standard deviations
     * each side, where the filtered signal cannot reach), not only the block: a record whose
     * amplitude grows or sweeps after the block still falls on the grid. */
    const double margin = 3.0 * out->noise_std; /* the raw extremes are mostly noise beyond */
    lo = c->lo + margin < lo ? c->lo + margin : lo;
    hi = c->hi - margin > hi ? c->hi - margin : hi;
    st = chan_bandwidth(c, y, hi - lo, opts, out, err);
    free(y);
    if (st != AENL_OK)
    {
        return st;
    }
    return chan_moments(c, name, lo, hi, out, err);
}

/**
 * Normalised autocorrelation rho(L) of white noise through the pre-filter, at the lags:
 * sum_k h_k h_{k+L} / sum_k h_k^2 over the impulse response h, run until it has decayed (its tail
 * below 1e-14 of the energy so far). Only the last L_max + 1 values of h are kept (a ring).
 * Returns 0 when out of memory (no correlation then).
 */
static int filter_acf(const aenl_filter_t *proto, const uint16_t *lags, uint16_t n_lags,
                      double *rho)
{
    uint16_t max_lag = 0;
    for (uint16_t i = 0; i < n_lags; ++i)
    {
        max_lag = lags[i] > max_lag ? lags[i] : max_lag;
    }
    const size_t len = (size_t)max_lag + 1u;
    double *ring = calloc(len, sizeof(double));
    if (ring == NULL)
    {
        return 0;
    }
    aenl_filter_t f = *proto;
    aenl_filter_reset(&f);
    double y = 0.0, prev = 0.0, e = 0.0;
    (void)aenl_filter_push(&f, 0.0, &y); /* primes at rest */
    double s[AENL_MOMENTS_MAX_LAGS] = {0.0};
    for (size_t n = 0; n < ((size_t)1 << 22); ++n)
    {
        (void)aenl_filter_push(&f, n == 0 ? 1.0 : 0.0, &y);
        for (uint16_t i = 0; i < n_lags; ++i)
        {
            if (n >= lags[i])
            {
                s[i] += y * ring[(n - lags[i]) % len];
            }
        }
        ring[n % len] = y;
        e += y * y;
        if (n > 64u && y * y < 1e-14 * e && prev * prev < 1e-14 * e)
        {
            break;
        }
        prev = y;
    }
    for (uint16_t i = 0; i < n_lags; ++i)
    {
        rho[i] = s[i] / e;
    }
    free(ring);
    return 1;
}

/** Read the display curves and the restoring-force points out of the moments. */
static aenl_status_t chan_export(const id_chan_t *c, aenl_identify_channel_t *out, uint16_t order,
                                 aenl_err_t *err)
{
    const size_t ng = out->n_grid > 0u ? out->n_grid : 1u, nd = out->n_display;
    out->x = malloc(ng * sizeof(double));
    out->mean = malloc(3u * (nd ? nd : 1u) * ng * sizeof(double));
    out->var = malloc(3u * (nd ? nd : 1u) * ng * sizeof(double));
    out->position = malloc(3u * ng * sizeof(double));
    out->accel = malloc(3u * ng * sizeof(double));
    if (out->x == NULL || out->mean == NULL || out->var == NULL || out->position == NULL ||
        out->accel == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    for (size_t k = 0; k < out->n_grid; ++k)
    {
        out->x[k] = aenl_moments_node_x(c->disp, (uint16_t)k);
        for (int d = 0; d < 3; ++d)
        {
            for (size_t l = 0; l < nd; ++l)
            {
                aenl_moments_point_t q;
                const int ok = aenl_moments_query(c->disp, (uint16_t)l, (uint16_t)k, (aenl_dir_t)d,
                                                  &q) == AENL_OK;
                out->mean[((size_t)d * nd + l) * ng + k] = ok ? q.mean : (double)NAN;
                out->var[((size_t)d * nd + l) * ng + k] = ok ? q.var : (double)NAN;
            }
            aenl_moments_taylor_t t;
            const int ok =
                aenl_moments_taylor(c->mom, (uint16_t)k, (aenl_dir_t)d, order, &t) == AENL_OK;
            out->position[(size_t)d * ng + k] = ok ? t.position : (double)NAN;
            out->accel[(size_t)d * ng + k] = ok ? t.accel : (double)NAN;
        }
    }
    return AENL_OK;
}

/* (Re)start the regression's pre-filters and settling count. */
static aenl_status_t rfs_filters_start(id_run_t *run)
{
    run->rfs_pushed = 0;
    aenl_rng_seed(&run->rfs_rng, ID_RFS_DITHER_SEED);
    for (size_t k = 0; k < run->n_ch; ++k)
    {
        if (aenl_filter_init(&run->rfs_filter[k], &run->rfs_fc) != AENL_OK)
        {
            return AENL_E_ARG;
        }
    }
    return AENL_OK;
}

/**
 * Set up the restoring-force regression after pass 1 (aenl_rfs.h): one low-pass for every
 * channel at ID_RFS_CUTOFF_CYCLES / (shortest dominant period), position lags 2..9 and 1/4, 1/2 of
 * the longest period, tents over each channel's grid. Left off (NULL) for a single channel, when
 * no channel oscillates, when one oscillates in a sustained, periodic way (autocorrelation at
 * ID_SUSTAINED_PERIODS periods >= 0.5, closer to a limit cycle's ~1 than to the damped response's
 * ~0: a linear recursion predicts a periodic record exactly, so the regression would be blind)
 * or when there are more channels than it takes; the core classifier's verdict then stands.
 */
static aenl_status_t rfs_setup(id_run_t *run, const aenl_identify_result_t *out, aenl_err_t *err)
{
    double p_min = 0.0, p_max = 0.0;
    for (size_t k = 0; k < run->n_ch; ++k)
    {
        const double p = out->ch[k].period;
        if (p > 0.0)
        {
            p_min = (p_min <= 0.0 || p < p_min) ? p : p_min;
            p_max = p > p_max ? p : p_max;
        }
    }
    int periodic = 0;
    for (size_t k = 0; k < run->n_ch; ++k)
    {
        periodic |= out->ch[k].sustained >= 0.5;
    }
    if (p_min <= 0.0 || periodic || run->n_ch < 2u || run->n_ch > AENL_RFS_MAX_CH)
    {
        return AENL_OK; /* one channel: no coupling to partial out, and its excitation (often a
                           deterministic input: multisine, sweep) is the equation error itself */
    }
    aenl_rfs_cfg_t rc;
    memset(&rc, 0, sizeof(rc));
    rc.n_ch = run->n_ch;
    rc.n_nodes = ID_RFS_NODES;
    rc.n_total = run->ch[0].n + run->ch[0].n_missing;
    for (size_t k = 0; k < run->n_ch; ++k)
    {
        const id_chan_t *c = &run->ch[k];
        rc.center[k] = c->mean;
        rc.scale[k] = c->n > 1u ? sqrt(c->m2 / (double)(c->n - 1u)) : 0.0;
        rc.lo[k] = out->ch[k].x_min;
        rc.hi[k] = out->ch[k].x_max;
        /* dither up to the noise floor, less the noise the channel already carries */
        const double fl = ID_RFS_NOISE_FLOOR * rc.scale[k], nz = out->ch[k].noise_std;
        run->rfs_dither[k] = fl > nz ? sqrt(fl * fl - nz * nz) : 0.0;
    }
    /* every lag from 2 to 9 (the states of the structure, the aerodynamics and the pre-filter
     * as a linear function of the past), then a quarter and a half of the longest period */
    for (uint16_t l = 2; l <= ID_RFS_DENSE_LAGS + 1u; ++l)
    {
        rc.lags[rc.n_lags++] = l;
    }
    for (unsigned div = 4; div >= 2u; div /= 2u)
    {
        const double l = floor(p_max / (double)div + 0.5);
        if (l > (double)rc.lags[rc.n_lags - 1u] && l < 65535.0)
        {
            rc.lags[rc.n_lags++] = (uint16_t)l;
        }
    }
    aenl_filter_cfg_t fc;
    fc.order = ID_FILTER_ORDER;
    fc.cutoff = ID_RFS_CUTOFF_CYCLES / p_min;
    fc.cutoff = fc.cutoff < 0.35 ? fc.cutoff : 0.35;
    run->rfs_settle = (size_t)ceil(4.0 / fc.cutoff);
    run->rfs_fc = fc;
    run->rfs_period = p_max;
    run->rfs_cfg = rc;
    run->rfs_filter = calloc(run->n_ch, sizeof(aenl_filter_t));
    run->rfs_row = calloc(run->n_ch, sizeof(double));
    run->rfs_res = calloc(run->n_ch, sizeof(double));
    run->rfs_kept = calloc(run->n_ch, sizeof(double));
    if (run->rfs_filter == NULL || run->rfs_row == NULL || run->rfs_res == NULL ||
        run->rfs_kept == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    if (rfs_filters_start(run) != AENL_OK)
    {
        aenl_err_set(err, "restoring-force regression: cannot design the pre-filter");
        return AENL_E_ARG;
    }
    return aenl_rfs_create(&run->rfs, &rc, err);
}

/*
 * Leave impulsive excitation out of the regression (aenl_impulse.h). A decay train's kicks, a
 * rap or a release are forces the equation of free motion does not have; every row whose
 * window holds one is an outlier that a law of the position can partly fit, consistently from
 * block to block, so it looks like a law. After pass 2: fit the free-law model, scan its
 * residuals (pass 3) and, when some window sum exceeds the threshold, accumulate the
 * regression again with the events left out (pass 4). The window is the pre-filter's impulse
 * response (2 / cutoff rows); an impulse must at least double the motion's energy over the
 * longest period; around one, the rows from that window plus 3 before its first exceedance to
 * one response plus 3 after it are left out.
 */
static aenl_status_t rfs_screen(id_run_t *run, double *row, aenl_identify_result_t *out,
                                aenl_err_t *err)
{
    aenl_status_t st = aenl_rfs_model(run->rfs, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const size_t response = (size_t)ceil(2.0 / run->rfs_fc.cutoff);
    aenl_impulse_cfg_t ic;
    ic.n_ch = run->n_ch;
    ic.window = response;
    ic.before = response + 3u;
    ic.after = response + 3u;
    ic.z = ID_IMPULSE_Z;
    ic.span = (size_t)ceil(run->rfs_period);
    ic.gain = ID_IMPULSE_GAIN;
    for (size_t k = 0; k < run->n_ch; ++k)
    {
        ic.center[k] = run->rfs_cfg.center[k];
        ic.scale[k] = run->rfs_cfg.scale[k];
    }
    if ((st = aenl_impulse_create(&run->imp, &ic, err)) != AENL_OK)
    {
        return st;
    }
    (void)rfs_filters_start(run);
    if ((st = for_rows(run->src, row, screen_row, run, err)) != AENL_OK ||
        !aenl_impulse_arm(run->imp))
    {
        return st;
    }
    /* Between impulses the motion is free, and its state is the recent past: the dense lags.
     * The longer lags (turbulence memory) would reach across the impulses and cost the rows
     * after each of them. */
    aenl_rfs_cfg_t rc = run->rfs_cfg;
    rc.n_lags = rc.n_lags < ID_RFS_DENSE_LAGS ? rc.n_lags : (uint16_t)ID_RFS_DENSE_LAGS;
    if ((st = aenl_rfs_create(&run->rfs_again, &rc, err)) != AENL_OK)
    {
        return st;
    }
    (void)rfs_filters_start(run);
    aenl_rfs_rewind(run->rfs);
    if ((st = for_rows(run->src, row, screen_row, run, err)) != AENL_OK)
    {
        return st;
    }
    int left_out = 0;
    while (aenl_impulse_drain(run->imp, run->rfs_kept, &left_out))
    {
        rfs_push_kept(run, left_out);
    }
    out->impulses = aenl_impulse_events(run->imp);
    out->impulse_rows = aenl_impulse_left_out(run->imp);
    out->decay_train = aenl_impulse_decaying(run->imp);
    if (out->impulses > 0) /* else the first accumulation, with every lag, stands */
    {
        aenl_rfs_free(run->rfs);
        run->rfs = run->rfs_again;
        run->rfs_again = NULL;
    }
    return AENL_OK;
}

/* Copy a restoring-force fit into a classifier-style result (class, weights, points). */
static void rfs_to_result(const aenl_rfs_fit_t *f, aenl_classifier_result_t *r)
{
    r->cls = f->cls;
    r->confidence = (aenl_real_t)f->confidence;
    for (int i = 0; i < AENL_CLASS_COUNT; ++i)
    {
        r->prob[i] = (aenl_real_t)f->prob[i];
    }
    r->hardening = (int8_t)(f->cls == AENL_CLASS_POLYNOMIAL ? f->hardening : 0);
    r->n_switch = (uint8_t)f->n_points;
    for (size_t i = 0; i < AENL_CLASSIFIER_MAX_SWITCH; ++i)
    {
        r->switch_points[i] = (aenl_real_t)(i < f->n_points ? f->points[i] : 0.0);
        r->switch_std[i] = (aenl_real_t)(i < f->n_points ? f->point_std[i] : 0.0);
    }
    r->evidence = (aenl_real_t)f->evidence;
}

/*
 * Which of several channels with a law holds the nonlinearity. A nonlinear force in one DOF
 * reaches the equation of every other through the coupling, and there, as a function of a
 * position that moves with its own, it can pass for a law of that channel. So each channel's
 * law is analysed again with each other channel's law among its regressors: a law the other
 * explains (the channel is then linear) while it does not explain the other's in turn is that
 * other's echo, and the channel is linear. Two laws that explain each other cannot be told
 * apart this way; both stand.
 */
static aenl_status_t explain_away(const aenl_rfs_t *rfs, aenl_identify_result_t *out,
                                  aenl_err_t *err)
{
    const size_t n = out->n_channels;
    size_t with_law = 0;
    for (size_t k = 0; k < n; ++k)
    {
        with_law += out->ch[k].rfs.cls > AENL_CLASS_LINEAR;
    }
    if (with_law < 2u)
    {
        return AENL_OK; /* no other law to explain one */
    }
    aenl_rfs_fit_t *given = malloc(n * n * sizeof(*given)); /* [j][i]: j given i's law */
    int expl[AENL_RFS_MAX_CH][AENL_RFS_MAX_CH] = {{0}};
    if (given == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    for (size_t j = 0; j < n; ++j)
    {
        for (size_t i = 0; i < n; ++i)
        {
            if (i == j || out->ch[i].rfs.cls <= AENL_CLASS_LINEAR ||
                out->ch[j].rfs.cls <= AENL_CLASS_LINEAR)
            {
                continue;
            }
            aenl_err_t e2;
            aenl_err_clear(&e2);
            const aenl_status_t st =
                aenl_rfs_analyse_given(rfs, j, i, &out->ch[i].rfs, &given[j * n + i], &e2);
            if (st != AENL_OK && st != AENL_E_NUMERIC)
            {
                *err = e2;
                free(given);
                return st;
            }
            /* a law collinear with the linear terms (degenerate) explains nothing */
            expl[j][i] = st == AENL_OK && given[j * n + i].cls == AENL_CLASS_LINEAR;
        }
    }
    /* every echo is found on the laws as found; then it takes its analysis given the law that
     * explains it (linear, with its weights) */
    long echo[AENL_RFS_MAX_CH];
    for (size_t j = 0; j < n; ++j)
    {
        echo[j] = -1;
        for (size_t i = 0; i < n && echo[j] < 0; ++i)
        {
            echo[j] = expl[j][i] && !expl[i][j] ? (long)i : -1;
        }
    }
    for (size_t j = 0; j < n; ++j)
    {
        out->ch[j].explained_by = echo[j];
        if (echo[j] >= 0)
        {
            out->ch[j].rfs = given[j * n + (size_t)echo[j]];
        }
    }
    free(given);
    return AENL_OK;
}

/*
 * The host verdict from both analyses. Where the restoring-force regression found a law in
 * some channel, it decides: it partials the other channels' motion out, so a linear channel
 * driven by a nonlinear one shows no law of its own, and it leaves impulsive excitation out
 * (rfs_screen), where the core classifier's conditional moments take a decay train's kicks,
 * or a neighbour's law, for a law of the channel. Every channel it judged takes its result (a
 * channel it could not judge keeps the core's, but is not named); the verdict is the channel
 * whose law has the largest evidence. Where it found no law anywhere, that is the verdict
 * (linear) on a train of kicked decays (at least one impulse per cross-validation block, and
 * the motion decaying between them: turbulence has bursts that pass for impulses), which the
 * core classifier cannot see past; on any other record the core classifier's verdicts stand, as
 * they do where the regression did not run (a limit cycle is periodic, so a linear recursion
 * on the lagged samples predicts it exactly and the regression is blind; one channel): on a
 * single free decay of a real rig its evidence weighs how much the law matters, where the
 * regression's polynomial can fail out of sample. Returns 1 when it named the verdict
 * (out->verdict, out->verdict_class set), 0 to leave it to the core's evidence.
 */
static int combine_verdicts(aenl_identify_result_t *out, int have_rfs)
{
    int judged = 0, decisive = 0;
    for (size_t k = 0; have_rfs && k < out->n_channels; ++k)
    {
        judged |= out->ch[k].rfs.cls >= AENL_CLASS_LINEAR;
        decisive |= out->ch[k].rfs.cls > AENL_CLASS_LINEAR;
    }
    if (!judged || (!decisive && !(out->decay_train && out->impulses >= AENL_RFS_BLOCKS)))
    {
        return 0;
    }
    out->verdict = -1;
    out->verdict_class = AENL_CLASS_LINEAR;
    for (size_t k = 0; k < out->n_channels; ++k)
    {
        aenl_identify_channel_t *c = &out->ch[k];
        if (c->rfs.cls < AENL_CLASS_LINEAR)
        {
            continue;
        }
        rfs_to_result(&c->rfs, &c->res);
        c->evidence = c->rfs.cls > AENL_CLASS_LINEAR ? c->rfs.evidence : 0.0;
        if (c->rfs.cls > AENL_CLASS_LINEAR &&
            (out->verdict < 0 || c->evidence > out->ch[out->verdict].evidence))
        {
            out->verdict = (long)k;
            out->verdict_class = c->rfs.cls;
        }
    }
    return 1;
}

/*
 * A limit cycle is not linear. The record's motion is one when a channel oscillates in a
 * sustained way (autocorrelation at ID_SUSTAINED_PERIODS periods >= 0.5) with a constant
 * amplitude (kurtosis below ID_LIMIT_CYCLE_KURTOSIS: a Gaussian process, the response of a linear
 * structure to turbulence however lightly damped, has 3). An unforced linear structure either
 * decays or grows; it has no stable periodic motion of its own. When the core classifier calls
 * every channel of such a record linear (its law is too smooth for the points to tell), the
 * verdict is the polynomial, in the channel where the polynomial's posterior weight is largest,
 * provided that weight is the largest among the nonlinear laws there; its confidence is that
 * weight relative to the nonlinear laws', and the channel's share is its polynomial weight among
 * those of the channels called linear. Only the polynomial needs no switching points, so the
 * gap laws are left to the classifier's own decision. A forced record (opts->forced: a shaker,
 * a stepped sine, a rotor tone) has no limit cycle to find. Returns 1 when it named the verdict.
 */
static int limit_cycle_verdict(aenl_identify_result_t *out, int forced)
{
    out->limit_cycle = -1;
    for (size_t k = 0; !forced && k < out->n_channels; ++k)
    {
        const aenl_identify_channel_t *c = &out->ch[k];
        if (c->sustained >= 0.5 && c->kurtosis > 0.0 && c->kurtosis < ID_LIMIT_CYCLE_KURTOSIS &&
            (out->limit_cycle < 0 || c->kurtosis < out->ch[out->limit_cycle].kurtosis))
        {
            out->limit_cycle = (long)k;
        }
    }
    if (out->limit_cycle < 0 || out->verdict_class != AENL_CLASS_LINEAR)
    {
        return 0;
    }
    long best = -1;
    double linear_poly = 0.0; /* the polynomial weights of the channels called linear */
    for (size_t k = 0; k < out->n_channels; ++k)
    {
        const aenl_classifier_result_t *rk = &out->ch[k].res;
        if (rk->cls != AENL_CLASS_LINEAR)
        {
            continue;
        }
        linear_poly += (double)rk->prob[AENL_CLASS_POLYNOMIAL];
        if (best < 0 ||
            rk->prob[AENL_CLASS_POLYNOMIAL] > out->ch[best].res.prob[AENL_CLASS_POLYNOMIAL])
        {
            best = (long)k;
        }
    }
    if (best < 0)
    {
        return 0;
    }
    aenl_classifier_result_t *r = &out->ch[best].res;
    double nonlinear = 0.0;
    for (int c = AENL_CLASS_POLYNOMIAL; c < AENL_CLASS_COUNT; ++c)
    {
        nonlinear += r->prob[c];
    }
    if (!(r->prob[AENL_CLASS_POLYNOMIAL] > 0.0) ||
        r->prob[AENL_CLASS_POLYNOMIAL] < r->prob[AENL_CLASS_FREEPLAY] ||
        r->prob[AENL_CLASS_POLYNOMIAL] < r->prob[AENL_CLASS_HYSTERESIS])
    {
        return 0;
    }
    out->verdict_share = (double)r->prob[AENL_CLASS_POLYNOMIAL] / linear_poly;
    r->cls = AENL_CLASS_POLYNOMIAL;
    r->confidence = (aenl_real_t)(r->prob[AENL_CLASS_POLYNOMIAL] / nonlinear);
    r->n_switch = 0;
    out->verdict = best;
    out->verdict_class = AENL_CLASS_POLYNOMIAL;
    return 1;
}

/* The named channel's share of the evidence of the channels with a nonlinear law that could
 * have been named (by_rfs: the regression's laws, whose t is the evidence; else the core
 * classifier's): the verdict names one of them, by its evidence, and is only as sure of the
 * channel as that share. */
static double evidence_share(const aenl_identify_result_t *out, int by_rfs)
{
    double sum = 0.0;
    for (size_t k = 0; k < out->n_channels; ++k)
    {
        const aenl_identify_channel_t *c = &out->ch[k];
        const aenl_class_t cls = by_rfs ? c->rfs.cls : c->res.cls;
        sum += cls > AENL_CLASS_LINEAR && c->evidence > 0.0 ? c->evidence : 0.0;
    }
    const double e = out->ch[out->verdict].evidence;
    return sum > 0.0 && e > 0.0 ? e / sum : 1.0;
}

/* The verdict's confidence (aenl_identify_result_t.verdict_confidence): the class given the
 * channel, as the channel's laws weigh it, times the channel's share. On a limit cycle the laws
 * are not weighed: over one orbit every channel is a periodic function of one phase, a law
 * depending on the direction of motion is any function of it and a law the same both ways any
 * even one of it, so the coupling's harmonics match each law as well as the law itself does and
 * the criterion gains between the nonlinear laws measure the orbit's shape, not the law. (A gap's
 * kink in time of the acceleration is the one trace the smooth coupling cannot copy; at practical
 * noise it is tens of dB below the noise even over the folded cycles: docs/identify.md.)
 * The record says only that the structure is nonlinear: each of the nonlinear classes is as
 * likely. */
static double verdict_confidence(const aenl_identify_result_t *out)
{
    if (out->verdict >= 0 && (size_t)out->verdict < out->n_channels)
    {
        const double cls = out->limit_cycle >= 0
                               ? 1.0 / (double)(AENL_CLASS_COUNT - AENL_CLASS_POLYNOMIAL)
                               : (double)out->ch[out->verdict].res.confidence;
        return cls * out->verdict_share;
    }
    double conf = 1.0;
    int any = 0;
    for (size_t k = 0; k < out->n_channels; ++k)
    {
        const aenl_classifier_result_t *r = &out->ch[k].res;
        if (r->cls != AENL_CLASS_INSUFFICIENT)
        {
            any = 1;
            conf = fmin(conf, (double)r->confidence);
        }
    }
    return any ? conf : 0.0;
}

/* The options in effect (the defaults when opts is NULL) into *o; an error when out of range. */
static aenl_status_t run_opts(const aenl_identify_source_t *src, const aenl_identify_opts_t *opts,
                              aenl_identify_opts_t *o, aenl_err_t *err)
{
    aenl_identify_opts_default(o);
    if (opts != NULL)
    {
        *o = *opts;
    }
    if (!isfinite(o->bandwidth) || o->bandwidth < 0.0 || o->cv_max < 256u ||
        o->channel >= (long)src->n_cols)
    {
        aenl_err_set(err, "identify: bad options (bandwidth %g, cv_max %zu, channel %ld)",
                     o->bandwidth, o->cv_max, o->channel);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

/* The run's per-channel state, the result's channels and each channel's pass-1 block; `row` is
 * the caller's row buffer, checked here with the rest. */
static aenl_status_t run_alloc(id_run_t *run, const double *row, aenl_identify_result_t *out,
                               aenl_err_t *err)
{
    const aenl_identify_opts_t *o = run->opts;
    run->col = calloc(run->n_ch, sizeof(size_t));
    run->ch = calloc(run->n_ch, sizeof(id_chan_t));
    out->ch = calloc(run->n_ch, sizeof(aenl_identify_channel_t));
    if (run->col == NULL || run->ch == NULL || row == NULL || out->ch == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    out->n_channels = run->n_ch;
    for (size_t k = 0; k < run->n_ch; ++k)
    {
        run->col[k] = o->channel >= 0 ? (size_t)o->channel : k;
        out->ch[k].explained_by = -1;
        run->ch[k].block = malloc(o->cv_max * sizeof(double));
        if (run->ch[k].block == NULL)
        {
            aenl_err_set(err, "out of memory");
            return AENL_E_IO;
        }
    }
    return AENL_OK;
}

/* The passes over the source: pass 1 (counts, range, the block), the channels' set-up and the
 * regression's, pass 2 (the moments, the regression) and, with the regression, the impulse
 * screen (passes 3 and 4). */
static aenl_status_t run_passes(id_run_t *run, double *row, aenl_identify_result_t *out,
                                aenl_err_t *err)
{
    const aenl_identify_source_t *src = run->src;
    aenl_status_t st = for_rows(src, row, pass1_row, run, err);
    for (size_t k = 0; k < run->n_ch && st == AENL_OK; ++k)
    {
        st = chan_setup(&run->ch[k], src->names[run->col[k]], run->opts, &out->ch[k], err);
    }
    if (st == AENL_OK)
    {
        st = rfs_setup(run, out, err);
        for (size_t k = 0; k < run->n_ch && run->rfs != NULL; ++k)
        {
            out->ch[k].dither_std = run->rfs_dither[k];
        }
    }
    if (st == AENL_OK)
    {
        st = for_rows(src, row, pass2_row, run, err);
    }
    if (st == AENL_OK && run->rfs != NULL)
    {
        st = rfs_screen(run, row, out, err);
    }
    return st;
}

/* The core classifier's configuration for channel ch: the lag expansion's order and, behind a
 * pre-filter, the correlation the filter gives white noise at the lags. */
static void classifier_cfg(const id_chan_t *ch, const aenl_identify_channel_t *c,
                           aenl_classifier_cfg_t *cc)
{
    aenl_classifier_cfg_default(cc);
    cc->taylor_order = ID_TAYLOR_ORDER;
    if (ch->cutoff > 0.0)
    {
        double rho[AENL_MOMENTS_MAX_LAGS] = {0.0};
        cc->use_noise_acf = (uint8_t)filter_acf(&ch->filter, c->lags, c->n_lags, rho);
        for (uint16_t i = 0; i < c->n_lags; ++i)
        {
            cc->noise_acf[i] = rho[i];
        }
    }
}

/* Classify channel k (the core classifier, the regression's analysis when it ran) and export its
 * curves. *cls is the classifier, allocated at the first call (large at host capacities: not on
 * the stack); the caller frees it. */
static aenl_status_t classify_channel(const id_run_t *run, size_t k, aenl_classifier_t **cls,
                                      aenl_identify_result_t *out, aenl_err_t *err)
{
    aenl_identify_channel_t *c = &out->ch[k];
    const id_chan_t *ch = &run->ch[k];
    aenl_classifier_cfg_t cc;
    classifier_cfg(ch, c, &cc);
    if (*cls == NULL)
    {
        *cls = malloc(sizeof(**cls));
    }
    if (*cls == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    if (aenl_classifier_init(*cls, &cc) != AENL_OK ||
        aenl_classifier_update(*cls, ch->mom) != AENL_OK)
    {
        aenl_err_set(err, "channel %s: classifier rejected the estimator", c->name);
        return AENL_E_ARG;
    }
    c->onboard = *aenl_classifier_result(*cls);
    c->res = c->onboard;
    c->kurtosis = ch->s2 > 0.0 ? ch->n2 * ch->s4 / (ch->s2 * ch->s2) : 0.0;
    c->evidence = c->res.cls > AENL_CLASS_LINEAR ? c->res.evidence : 0.0;
    aenl_status_t st = AENL_OK;
    if (run->rfs != NULL)
    {
        st = aenl_rfs_analyse(run->rfs, k, &c->rfs, err);
    }
    if (st == AENL_OK)
    {
        st = chan_export(ch, c, cc.taylor_order, err);
    }
    return st;
}

/* Classify every channel (classify_channel). */
static aenl_status_t classify_channels(const id_run_t *run, aenl_identify_result_t *out,
                                       aenl_err_t *err)
{
    aenl_classifier_t *cls = NULL;
    aenl_status_t st = AENL_OK;
    for (size_t k = 0; k < run->n_ch && st == AENL_OK; ++k)
    {
        st = classify_channel(run, k, &cls, out, err);
    }
    free(cls);
    return st;
}

/* The core classifier's verdict: the nonlinear channel with the largest evidence; with none,
 * linear when some channel is linear, else insufficient. */
static void core_verdict(aenl_identify_result_t *out)
{
    out->verdict = -1;
    out->verdict_class = AENL_CLASS_INSUFFICIENT;
    double best = 0.0;
    for (size_t k = 0; k < out->n_channels; ++k)
    {
        const aenl_identify_channel_t *c = &out->ch[k];
        if (c->res.cls == AENL_CLASS_LINEAR && out->verdict < 0)
        {
            out->verdict_class = AENL_CLASS_LINEAR;
        }
        if (c->res.cls > AENL_CLASS_LINEAR && c->evidence > best)
        {
            best = c->evidence;
            out->verdict = (long)k;
            out->verdict_class = c->res.cls;
        }
    }
}

/* The verdict and its confidence: the regression's where it decides (combine_verdicts), else the
 * core classifier's, or the polynomial of a limit cycle (limit_cycle_verdict). */
static aenl_status_t run_verdict(const id_run_t *run, aenl_identify_result_t *out, aenl_err_t *err)
{
    if (run->rfs != NULL)
    {
        const aenl_status_t st = explain_away(run->rfs, out, err);
        if (st != AENL_OK)
        {
            return st;
        }
    }
    int named_by_cycle = 0; /* which rule named the verdict */
    const int named_by_rfs = combine_verdicts(out, run->rfs != NULL);
    if (!named_by_rfs)
    {
        core_verdict(out);
        named_by_cycle = limit_cycle_verdict(out, run->opts->forced);
    }
    if (out->verdict >= 0 && !named_by_cycle)
    {
        out->verdict_share = evidence_share(out, named_by_rfs);
    }
    out->verdict_confidence = verdict_confidence(out);
    return AENL_OK;
}

/* Everything the run holds (not the result). */
static void run_free(id_run_t *run)
{
    for (size_t k = 0; run->ch != NULL && k < run->n_ch; ++k)
    {
        chan_free(&run->ch[k]);
    }
    aenl_rfs_free(run->rfs);
    aenl_rfs_free(run->rfs_again);
    aenl_impulse_free(run->imp);
    free(run->rfs_filter);
    free(run->rfs_row);
    free(run->rfs_res);
    free(run->rfs_kept);
    free(run->ch);
    free(run->col);
}

aenl_status_t aenl_identify_run(const aenl_identify_source_t *src, const aenl_identify_opts_t *opts,
                                aenl_identify_result_t *out, aenl_err_t *err)
{
    if (src == NULL || out == NULL || src->n_cols == 0u)
    {
        aenl_err_set(err, "identify: no channels");
        return AENL_E_ARG;
    }
    memset(out, 0, sizeof(*out));
    out->limit_cycle = -1;
    aenl_identify_opts_t o;
    aenl_status_t st = run_opts(src, opts, &o, err);
    if (st != AENL_OK)
    {
        return st;
    }
    id_run_t run;
    memset(&run, 0, sizeof(run));
    run.src = src;
    run.opts = &o;
    run.n_ch = o.channel >= 0 ? 1u : src->n_cols;
    double *row = calloc(src->n_cols, sizeof(double));
    st = run_alloc(&run, row, out, err);
    if (st == AENL_OK)
    {
        st = run_passes(&run, row, out, err);
    }
    if (st == AENL_OK)
    {
        st = classify_channels(&run, out, err);
    }
    if (st == AENL_OK)
    {
        st = run_verdict(&run, out, err);
    }
    run_free(&run);
    free(row);
    if (st != AENL_OK)
    {
        aenl_identify_free(out);
    }
    return st;
}
