/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_impulse.c
 * @brief Screening of impulsive excitation from equation residuals (aenl_impulse.h).
 */
#include "aenl_tools/aenl_impulse.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/** |s| histogram: log10 from IMP_LOG_LO in IMP_PER_DECADE bins per decade. */
#define IMP_LOG_LO     (-16.0)
#define IMP_PER_DECADE 40.0
#define IMP_BINS       880u
/** A record is impulsive when its rows beyond the threshold exceed the Gaussian tail by this
 *  many standard errors. */
#define IMP_EXCESS_Z 3.0
/** An impulse's window sums exceed for about two windows (its pulse entering and leaving the
 *  window); a run of exceedances longer than this many windows is the model's own error. */
#define IMP_MAX_RUN 3u
/** Runs waiting for the motion after them (beyond this, the oldest is judged at once). */
#define IMP_MAX_PENDING 32u

static size_t delay_of(const aenl_impulse_cfg_t *c);
static int emit(aenl_impulse_t *s, double *out, int *left_out);

struct aenl_impulse
{
    aenl_impulse_cfg_t cfg;
    /* the window sums */
    double *box; /* [window][n_ch] */
    double sum[AENL_IMPULSE_MAX_CH];
    size_t fill[AENL_IMPULSE_MAX_CH]; /* valid rows in the window */
    size_t at;                        /* rows taken in this pass */
    /* pass 1 */
    size_t *hist; /* [n_ch][IMP_BINS] */
    double thr[AENL_IMPULSE_MAX_CH];
    /* pass 2: the delay line */
    double *held;         /* [delay + 1][n_ch] */
    double *row_e;        /* [delay + 1]: each held row's energy (NaN: a value missing) */
    unsigned char *out_f; /* [delay + 1]: left out */
    size_t mask_until;    /* rows up to this index (exclusive) are left out */
    size_t run_start, run_last;
    int in_run;
    size_t pending[IMP_MAX_PENDING]; /* starts of short runs awaiting the energy check */
    size_t n_pending;
    size_t drained;
    size_t events, left_out;
    /* the motion's energy over consecutive spans: how often it falls */
    double span_e, last_e;
    size_t span_n, spans, falls;
};

aenl_status_t aenl_impulse_create(aenl_impulse_t **out, const aenl_impulse_cfg_t *cfg,
                                  aenl_err_t *err)
{
    if (out == NULL || cfg == NULL || cfg->n_ch == 0 || cfg->n_ch > AENL_IMPULSE_MAX_CH ||
        cfg->window == 0 || cfg->before < cfg->window || !(cfg->z > 0.0) || !isfinite(cfg->z) ||
        cfg->span == 0 || !(cfg->gain >= 1.0) || !isfinite(cfg->gain))
    {
        aenl_err_set(err, "impulse screening: bad configuration");
        return AENL_E_ARG;
    }
    for (size_t k = 0; k < cfg->n_ch; ++k)
    {
        if (!(cfg->scale[k] > 0.0) || !isfinite(cfg->scale[k]) || !isfinite(cfg->center[k]))
        {
            aenl_err_set(err, "impulse screening: bad scale of channel %zu", k);
            return AENL_E_ARG;
        }
    }
    aenl_impulse_t *s = calloc(1, sizeof(*s));
    if (s == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    s->cfg = *cfg;
    s->box = calloc(cfg->window * cfg->n_ch, sizeof(double));
    s->hist = calloc(cfg->n_ch * IMP_BINS, sizeof(size_t));
    s->held = calloc((delay_of(cfg) + 1u) * cfg->n_ch, sizeof(double));
    s->out_f = calloc(delay_of(cfg) + 1u, 1);
    s->row_e = calloc(delay_of(cfg) + 1u, sizeof(double));
    if (s->box == NULL || s->hist == NULL || s->held == NULL || s->out_f == NULL ||
        s->row_e == NULL)
    {
        aenl_impulse_free(s);
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    *out = s;
    return AENL_OK;
}

void aenl_impulse_free(aenl_impulse_t *s)
{
    if (s != NULL)
    {
        free(s->box);
        free(s->hist);
        free(s->held);
        free(s->out_f);
        free(s->row_e);
        free(s);
    }
}

/* Take one row of residuals into the window sums; a NaN restarts its channel's sum. */
static void window_push(aenl_impulse_t *s, const double *e)
{
    const size_t nc = s->cfg.n_ch, w = s->cfg.window;
    double *slot = &s->box[(s->at % w) * nc];
    for (size_t k = 0; k < nc; ++k)
    {
        if (!isfinite(e[k]))
        {
            s->fill[k] = 0;
            s->sum[k] = 0.0;
            slot[k] = 0.0;
            continue;
        }
        s->sum[k] += e[k] - slot[k]; /* slot holds the row leaving the window (0 while filling) */
        slot[k] = e[k];
        s->fill[k] += s->fill[k] < w;
    }
    s->at++;
    if (s->at % w == 0u)
    {
        for (size_t k = 0; k < nc; ++k) /* the running sums restart from the window itself */
        {
            double t = 0.0;
            for (size_t i = 0; i < w; ++i)
            {
                t += s->box[i * nc + k];
            }
            s->sum[k] = t;
        }
    }
}

void aenl_impulse_scan(aenl_impulse_t *s, const double *e)
{
    if (s == NULL || e == NULL)
    {
        return;
    }
    window_push(s, e);
    for (size_t k = 0; k < s->cfg.n_ch; ++k)
    {
        if (s->fill[k] < s->cfg.window)
        {
            continue;
        }
        const double a = fabs(s->sum[k]);
        double b = a > 0.0 ? (log10(a) - IMP_LOG_LO) * IMP_PER_DECADE : 0.0;
        b = b < 0.0 ? 0.0 : (b > (double)(IMP_BINS - 1u) ? (double)(IMP_BINS - 1u) : b);
        s->hist[k * IMP_BINS + (size_t)b]++;
    }
}

/* The |s| a histogram bin stands for (its centre). */
static double bin_value(size_t i)
{
    return pow(10.0, IMP_LOG_LO + ((double)i + 0.5) / IMP_PER_DECADE);
}

int aenl_impulse_arm(aenl_impulse_t *s)
{
    if (s == NULL)
    {
        return 0;
    }
    int any = 0;
    for (size_t k = 0; k < s->cfg.n_ch; ++k)
    {
        const size_t *h = &s->hist[k * IMP_BINS];
        size_t n = 0, cum = 0, b = 0;
        for (size_t i = 0; i < IMP_BINS; ++i)
        {
            n += h[i];
        }
        s->thr[k] = INFINITY;
        if (n == 0)
        {
            continue;
        }
        while (b + 1u < IMP_BINS && 2u * (cum + h[b]) < n)
        {
            cum += h[b++];
        }
        s->thr[k] = s->cfg.z * bin_value(b) / 0.6744897501960817; /* z robust sd's */
        /* rows beyond the threshold against the Gaussian tail, with the sums' correlation
         * over a window: about n / window independent draws */
        size_t over = 0;
        for (size_t i = 0; i < IMP_BINS; ++i)
        {
            over += bin_value(i) > s->thr[k] ? h[i] : 0u;
        }
        const double p0 = erfc(s->cfg.z / sqrt(2.0));
        const double draws = (double)n / (double)s->cfg.window;
        any |= (double)over / (double)n > p0 + IMP_EXCESS_Z * sqrt(p0 * (1.0 - p0) / draws);
    }
    memset(s->box, 0, s->cfg.window * s->cfg.n_ch * sizeof(double));
    memset(s->sum, 0, sizeof(s->sum));
    memset(s->fill, 0, sizeof(s->fill));
    s->at = 0;
    return any;
}

/* Rows held back: a run of exceedances is judged once it has ended (a gap of more than a
 * window, at most IMP_MAX_RUN + 1 windows after it began) and `span` rows after its start are
 * in; the `span` rows before it (a window earlier) and its rows from `before` ahead must still
 * be held then. */
static size_t delay_of(const aenl_impulse_cfg_t *c)
{
    const size_t a = c->before + (IMP_MAX_RUN + 1u) * c->window;
    const size_t b = 2u * c->span + c->window;
    return (a > b ? a : b) + 1u;
}

/* The energy of one row: its standardised values' sum of squares (NaN when one is missing). */
static double row_energy(const aenl_impulse_t *s, const double *row)
{
    double v = 0.0;
    for (size_t k = 0; k < s->cfg.n_ch; ++k)
    {
        const double z = (row[k] - s->cfg.center[k]) / s->cfg.scale[k];
        v += z * z;
    }
    return v;
}

/* Mean energy of the held rows [from, to) (rows with a value missing skipped). */
static double energy(const aenl_impulse_t *s, size_t from, size_t to)
{
    const size_t ring = delay_of(&s->cfg) + 1u;
    double e = 0.0;
    size_t n = 0;
    for (size_t i = from; i < to; ++i)
    {
        const double v = s->row_e[i % ring];
        if (isfinite(v))
        {
            e += v;
            n++;
        }
    }
    return n > 0 ? e / (double)n : 0.0;
}

/* One row's energy v into the mean over consecutive spans of rows: count the spans after
 * which it fell. */
static void span_energy(aenl_impulse_t *s, double v)
{
    if (isfinite(v))
    {
        s->span_e += v;
        s->span_n++;
    }
    if ((s->at % s->cfg.span) != 0u || s->span_n == 0u)
    {
        return;
    }
    const double e = s->span_e / (double)s->span_n;
    if (s->spans > 0u)
    {
        s->falls += e < s->last_e;
    }
    s->spans++;
    s->last_e = e;
    s->span_e = 0.0;
    s->span_n = 0;
}

/* Judge the oldest waiting run: an impulse from outside puts energy into the motion, so the
 * motion's mean square over `span` rows from the run's start must exceed `gain` times that over
 * the `span` rows before (a window ahead of the start, where s may already rise). A misfit of
 * the model (at a freeplay contact, say) leaves the energy as it was. An impulse's rows from
 * `before` ahead of the start to `after` past it are left out. */
static void judge(aenl_impulse_t *s)
{
    const size_t ring = delay_of(&s->cfg) + 1u, start = s->pending[0];
    s->n_pending--;
    memmove(s->pending, s->pending + 1, s->n_pending * sizeof(size_t));
    const size_t w = s->cfg.window, span = s->cfg.span;
    const size_t b1 = start > w ? start - w : 0u, b0 = b1 > span ? b1 - span : 0u;
    const size_t a1 = start + span < s->at ? start + span : s->at;
    const double before = energy(s, b0 > s->drained ? b0 : s->drained, b1);
    const double after = energy(s, start, a1);
    if (!(after > s->cfg.gain * before))
    {
        return;
    }
    s->events++;
    const size_t from = start > s->cfg.before ? start - s->cfg.before : 0u;
    const size_t to = start + s->cfg.after; /* inclusive */
    for (size_t i = from > s->drained ? from : s->drained; i <= to && i < s->at; ++i)
    {
        s->out_f[i % ring] = 1;
    }
    s->mask_until = to + 1u > s->mask_until ? to + 1u : s->mask_until;
}

/* The run of exceedances that began at run_start has ended at row `last`: a short one waits
 * for the energy check; a sustained one is the model's own error. */
static void run_end(aenl_impulse_t *s, size_t last)
{
    s->in_run = 0;
    if (last - s->run_start + 1u > IMP_MAX_RUN * s->cfg.window)
    {
        return;
    }
    if (s->n_pending == IMP_MAX_PENDING)
    {
        judge(s);
    }
    s->pending[s->n_pending++] = s->run_start;
}

int aenl_impulse_step(aenl_impulse_t *s, const double *e, const double *row, double *out,
                      int *left_out)
{
    if (s == NULL || e == NULL || row == NULL || out == NULL || left_out == NULL)
    {
        return 0;
    }
    const size_t nc = s->cfg.n_ch, delay = delay_of(&s->cfg), ring = delay + 1u, n = s->at;
    window_push(s, e);
    int exceed = 0;
    for (size_t k = 0; k < nc; ++k)
    {
        exceed |= s->fill[k] == s->cfg.window && fabs(s->sum[k]) > s->thr[k];
    }
    memcpy(&s->held[(n % ring) * nc], row, nc * sizeof(double));
    s->row_e[n % ring] = row_energy(s, row);
    span_energy(s, s->row_e[n % ring]);
    s->out_f[n % ring] = n < s->mask_until;
    if (exceed)
    {
        if (!s->in_run)
        {
            s->in_run = 1;
            s->run_start = n;
        }
        s->run_last = n;
    }
    else if (s->in_run && n - s->run_last > s->cfg.window)
    {
        run_end(s, s->run_last);
    }
    while (s->n_pending > 0 && s->pending[0] + s->cfg.span <= s->at)
    {
        judge(s);
    }
    return n < delay ? 0 : emit(s, out, left_out);
}

int aenl_impulse_drain(aenl_impulse_t *s, double *out, int *left_out)
{
    if (s == NULL || out == NULL || left_out == NULL || s->drained >= s->at)
    {
        return 0;
    }
    if (s->in_run)
    {
        run_end(s, s->run_last); /* the record ended inside a run */
    }
    while (s->n_pending > 0) /* judged on the rows there are */
    {
        judge(s);
    }
    return emit(s, out, left_out);
}

/* The oldest row held. */
static int emit(aenl_impulse_t *s, double *out, int *left_out)
{
    const size_t nc = s->cfg.n_ch, slot = s->drained % (delay_of(&s->cfg) + 1u);
    memcpy(out, &s->held[slot * nc], nc * sizeof(double));
    *left_out = s->out_f[slot];
    s->left_out += s->out_f[slot];
    s->drained++;
    return 1;
}

int aenl_impulse_decaying(const aenl_impulse_t *s)
{
    if (s == NULL || s->spans < 2u)
    {
        return 0;
    }
    const double m = (double)(s->spans - 1u);
    return (double)s->falls > 0.5 * m + IMP_EXCESS_Z * 0.5 * sqrt(m);
}

size_t aenl_impulse_events(const aenl_impulse_t *s)
{
    return s != NULL ? s->events : 0u;
}

size_t aenl_impulse_left_out(const aenl_impulse_t *s)
{
    return s != NULL ? s->left_out : 0u;
}

double aenl_impulse_threshold(const aenl_impulse_t *s, size_t ch)
{
    return (s != NULL && ch < s->cfg.n_ch) ? s->thr[ch] : 0.0;
}
