/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose_sig.c
 * @brief Signatures of one channel for the diagnosis: settings fixed from the measured record,
 *        amplitude quantiles and envelope, conditional mean/std curves, Welch spectrum, and the
 *        normalised family distances (docs/diagnose.md, "The gap metric").
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl/aenl_filter.h"
#include "aenl_diagnose_internal.h"
#include "aenl_tools/aenl_curves.h"
#include "aenl_tools/aenl_sort.h"

const double aenl_diagnose_quant_p[AENL_DIAGNOSE_N_QUANT] = {0.01, 0.05, 0.1,  0.25, 0.5,
                                                             0.75, 0.9,  0.95, 0.99};

static const double k_pi = 3.14159265358979323846;

/* ---- FFT and Welch ------------------------------------------------------------------------ */

/* In-place iterative radix-2 FFT of re/im (n a power of two). */
static void fft(double *re, double *im, size_t n)
{
    for (size_t i = 1, j = 0; i < n; ++i)
    {
        size_t bit = n >> 1u;
        for (; j & bit; bit >>= 1u)
        {
            j ^= bit;
        }
        j ^= bit;
        if (i < j)
        {
            double t = re[i];
            re[i] = re[j];
            re[j] = t;
            t = im[i];
            im[i] = im[j];
            im[j] = t;
        }
    }
    for (size_t len = 2; len <= n; len <<= 1u)
    {
        const double ang = -2.0 * k_pi / (double)len;
        const double wr = cos(ang), wi = sin(ang);
        for (size_t i = 0; i < n; i += len)
        {
            double cr = 1.0, ci = 0.0;
            for (size_t k = 0; k < len / 2u; ++k)
            {
                const size_t a = i + k, b = i + k + len / 2u;
                const double tr = re[b] * cr - im[b] * ci;
                const double ti = re[b] * ci + im[b] * cr;
                re[b] = re[a] - tr;
                im[b] = im[a] - ti;
                re[a] += tr;
                im[a] += ti;
                const double nr = cr * wr - ci * wi;
                ci = cr * wi + ci * wr;
                cr = nr;
            }
        }
    }
}

static double mean_of(const double *x, size_t n)
{
    double m = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        m += x[i];
    }
    return m / (double)n;
}

aenl_status_t aenl_diagnose_welch(const double *x, size_t n, size_t seg, double *psd,
                                  aenl_err_t *err)
{
    if (seg < 8u || (seg & (seg - 1u)) != 0u || seg > AENL_DIAGNOSE_MAX_SEG || n < seg)
    {
        aenl_err_set(err, "Welch: segment %zu is not a power of two in 8..%d within %zu samples",
                     seg, AENL_DIAGNOSE_MAX_SEG, n);
        return AENL_E_ARG;
    }
    double *re = malloc(2u * seg * sizeof(double));
    if (re == NULL)
    {
        aenl_err_set(err, "out of memory (Welch segment)");
        return AENL_E_DIM;
    }
    double *im = re + seg;
    const double mean = mean_of(x, n);
    double wsum = 0.0;
    for (size_t i = 0; i < seg; ++i)
    {
        const double w = 0.5 - 0.5 * cos(2.0 * k_pi * (double)i / (double)seg);
        wsum += w * w;
    }
    const size_t nb = seg / 2u + 1u;
    memset(psd, 0, nb * sizeof(double));
    size_t n_seg = 0;
    for (size_t s0 = 0; s0 + seg <= n; s0 += seg / 2u)
    {
        for (size_t i = 0; i < seg; ++i)
        {
            const double w = 0.5 - 0.5 * cos(2.0 * k_pi * (double)i / (double)seg);
            re[i] = w * (x[s0 + i] - mean);
            im[i] = 0.0;
        }
        fft(re, im, seg);
        for (size_t k = 0; k < nb; ++k)
        {
            const double p = (re[k] * re[k] + im[k] * im[k]) / wsum;
            psd[k] += (k == 0u || k == nb - 1u) ? p : 2.0 * p;
        }
        n_seg++;
    }
    for (size_t k = 0; k < nb; ++k)
    {
        psd[k] /= (double)n_seg; /* one-sided, per cycle-per-sample */
    }
    free(re);
    return AENL_OK;
}

/* Peak of a PSD over bins [k0, nb-1) (k0 >= 1), refined by a parabola through the log values;
 * in bins. */
static double psd_peak(const double *psd, size_t nb, size_t k0)
{
    size_t k_best = k0;
    for (size_t k = k0; k + 1u < nb; ++k)
    {
        if (psd[k] > psd[k_best])
        {
            k_best = k;
        }
    }
    if (k_best + 1u >= nb || !(psd[k_best - 1u] > 0.0) || !(psd[k_best + 1u] > 0.0) ||
        !(psd[k_best] > 0.0))
    {
        return (double)k_best;
    }
    const double a = log(psd[k_best - 1u]), b = log(psd[k_best]), c = log(psd[k_best + 1u]);
    const double den = a - 2.0 * b + c;
    const double off = (den < 0.0) ? 0.5 * (a - c) / den : 0.0;
    return (double)k_best + (fabs(off) < 1.0 ? off : 0.0);
}

aenl_status_t aenl_diagnose_peak_freq(const double *x, size_t n, double *freq, aenl_err_t *err)
{
    if (n < 16u || n > ((size_t)1 << 24u))
    {
        aenl_err_set(err, "peak frequency: %zu samples (16 .. 2^24)", n);
        return AENL_E_ARG;
    }
    size_t nfft = 8u;
    while (nfft < 4u * n)
    {
        nfft <<= 1u;
    }
    double *re = calloc(2u * nfft, sizeof(double));
    if (re == NULL)
    {
        aenl_err_set(err, "out of memory (periodogram)");
        return AENL_E_DIM;
    }
    double *im = re + nfft;
    const double mean = mean_of(x, n);
    for (size_t i = 0; i < n; ++i)
    {
        const double w = 0.5 - 0.5 * cos(2.0 * k_pi * ((double)i + 0.5) / (double)n);
        re[i] = w * (x[i] - mean);
    }
    fft(re, im, nfft);
    const size_t nb = nfft / 2u + 1u;
    for (size_t k = 0; k < nb; ++k)
    {
        re[k] = re[k] * re[k] + im[k] * im[k];
    }
    /* from two bins of the unpadded record on: past the window's main lobe at zero */
    *freq = psd_peak(re, nb, 2u * (nfft / n)) / (double)nfft;
    free(re);
    return AENL_OK;
}

static size_t pow2_floor(size_t v)
{
    size_t p = 1;
    while (p * 2u <= v)
    {
        p *= 2u;
    }
    return p;
}

/* ---- pre-filter ----------------------------------------------------------------------------- */

/* Low-pass copy of x (4th-order Butterworth); NULL when out of memory or a bad cutoff. */
static double *lowpass(const double *x, size_t n, double cutoff)
{
    aenl_filter_t f;
    aenl_filter_cfg_t cfg;
    memset(&cfg, 0, sizeof(cfg));
    cfg.cutoff = cutoff;
    cfg.order = 4;
    if (aenl_filter_init(&f, &cfg) != AENL_OK)
    {
        return NULL;
    }
    double *y = malloc((n ? n : 1u) * sizeof(double));
    if (y == NULL)
    {
        return NULL;
    }
    for (size_t i = 0; i < n; ++i)
    {
        (void)aenl_filter_push(&f, x[i], &y[i]);
    }
    return y;
}

/* ---- settings ---------------------------------------------------------------------------------
 */

/* Robust white-noise std from third differences: var(d3) = 20 sigma^2 for white noise, and the
 * median absolute deviation ignores the (small) smooth-signal part and isolated glitches. */
static aenl_status_t noise_std(const double *x, size_t n, double *out, aenl_err_t *err)
{
    const size_t m = n - 3u;
    double *d = malloc(m * sizeof(double));
    if (d == NULL)
    {
        aenl_err_set(err, "out of memory (noise estimate)");
        return AENL_E_DIM;
    }
    for (size_t i = 0; i < m; ++i)
    {
        d[i] = x[i + 3u] - 3.0 * x[i + 2u] + 3.0 * x[i + 1u] - x[i];
    }
    double med = 0.0;
    double sd = 0.0;
    aenl_median_mad(d, m, &med, &sd);
    *out = sd / sqrt(20.0);
    free(d);
    return AENL_OK;
}

static void set_bands(aenl_diagnose_chan_t *c)
{
    const double f_dom = 1.0 / c->period;
    const double f_lo = f_dom / 6.0;
    const double f_hi = fmin(0.5, 6.0 * f_dom);
    const double seg = (double)c->seg;
    const size_t nb = c->seg / 2u + 1u;
    size_t prev_hi = 1;
    c->n_bands = 0;
    for (size_t b = 0; b < AENL_DIAGNOSE_N_BANDS; ++b)
    {
        const double e0 = f_lo * pow(f_hi / f_lo, (double)b / AENL_DIAGNOSE_N_BANDS);
        const double e1 = f_lo * pow(f_hi / f_lo, (double)(b + 1u) / AENL_DIAGNOSE_N_BANDS);
        size_t lo = (size_t)floor(e0 * seg + 0.5);
        size_t hi = (size_t)floor(e1 * seg + 0.5);
        lo = lo < prev_hi ? prev_hi : lo;
        hi = hi > nb ? nb : hi;
        if (hi <= lo)
        {
            continue;
        }
        c->band_lo[c->n_bands] = lo;
        c->band_hi[c->n_bands] = hi;
        c->n_bands++;
        prev_hi = hi;
    }
}

aenl_status_t aenl_diagnose_chan_setup(const double *x, size_t n, aenl_diagnose_chan_t *c,
                                       aenl_err_t *err)
{
    memset(c, 0, sizeof(*c));
    if (n < 512u)
    {
        aenl_err_set(err, "%zu samples: at least 512 are needed", n);
        return AENL_E_ARG;
    }
    double s1 = 0.0, s2 = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        if (!isfinite(x[i]))
        {
            aenl_err_set(err, "sample %zu is missing or not finite (gaps are not supported)", i);
            return AENL_E_ARG;
        }
        s1 += x[i];
    }
    const double mean = s1 / (double)n;
    for (size_t i = 0; i < n; ++i)
    {
        s2 += (x[i] - mean) * (x[i] - mean);
    }
    c->scale = sqrt(s2 / (double)n);
    if (!(c->scale > 1e-300) || !isfinite(c->scale))
    {
        aenl_err_set(err, "the channel is constant");
        return AENL_E_ARG;
    }
    aenl_status_t st = noise_std(x, n, &c->noise_sd, err);
    c->noise_record = c->noise_sd;
    if (st != AENL_OK)
    {
        return st;
    }
    /* Dominant period from a first Welch spectrum. */
    const size_t seg0 = pow2_floor(n / 4u < 4096u ? n / 4u : 4096u);
    double *psd = malloc((seg0 / 2u + 1u) * sizeof(double));
    if (psd == NULL)
    {
        aenl_err_set(err, "out of memory (spectrum)");
        return AENL_E_DIM;
    }
    st = aenl_diagnose_welch(x, n, seg0, psd, err);
    if (st == AENL_OK)
    {
        const double k = psd_peak(psd, seg0 / 2u + 1u, 2u);
        c->period = (double)seg0 / (k > 1.0 ? k : 1.0);
    }
    free(psd);
    if (st != AENL_OK)
    {
        return st;
    }
    c->period = fmax(4.0, fmin(c->period, (double)n / 4.0));
    c->cutoff = fmin(0.4, 4.0 / c->period);
    c->settle = (size_t)ceil(4.0 / c->cutoff);
    if (c->settle * 4u > n)
    {
        c->settle = n / 4u;
    }
    const double fr[AENL_DIAGNOSE_N_LAGS] = {16.0, 8.0, 4.0};
    for (size_t i = 0; i < AENL_DIAGNOSE_N_LAGS; ++i)
    {
        double v = floor(c->period / fr[i] + 0.5);
        v = fmax(1.0, fmin(v, (double)AENL_MOMENTS_MAX_LAG));
        uint16_t lag = (uint16_t)v;
        if (i > 0u && lag <= c->lags[i - 1u])
        {
            lag = (uint16_t)(c->lags[i - 1u] + 1u);
        }
        c->lags[i] = lag;
    }
    if (c->lags[AENL_DIAGNOSE_N_LAGS - 1u] > AENL_MOMENTS_MAX_LAG)
    {
        for (size_t i = 0; i < AENL_DIAGNOSE_N_LAGS; ++i)
        {
            c->lags[i] = (uint16_t)(AENL_MOMENTS_MAX_LAG - (AENL_DIAGNOSE_N_LAGS - 1u - i) * 8u);
        }
    }
    double *y = lowpass(x, n, c->cutoff);
    if (y == NULL)
    {
        aenl_err_set(err, "out of memory (pre-filter)");
        return AENL_E_DIM;
    }
    const size_t m = n - c->settle;
    double *s = y + c->settle;
    double ym = 0.0;
    for (size_t i = 0; i < m; ++i)
    {
        ym += s[i];
    }
    c->mean = ym / (double)m;
    aenl_sort_doubles(s, m);
    c->x_min = aenl_quantile_sorted(s, m, 0.01);
    c->x_max = aenl_quantile_sorted(s, m, 0.99);
    free(y);
    if (!(c->x_max > c->x_min))
    {
        aenl_err_set(err, "the pre-filtered channel is constant");
        return AENL_E_ARG;
    }
    c->bandwidth = 2.0 * (c->x_max - c->x_min) / (double)(AENL_DIAGNOSE_N_GRID - 1u);
    double want = 8.0 * c->period;
    size_t seg = pow2_floor((size_t)want);
    seg = seg < 64u ? 64u : seg;
    seg = seg > seg0 ? seg0 : seg;
    c->seg = seg;
    set_bands(c);
    return AENL_OK;
}

/* ---- signature ---------------------------------------------------------------------------- */

static aenl_status_t curves_of(const double *y, size_t m, const aenl_diagnose_chan_t *c,
                               aenl_diagnose_sig_t *s, aenl_err_t *err)
{
    aenl_curves_opts_t o;
    aenl_curves_opts_default(&o);
    o.n_lags = AENL_DIAGNOSE_N_LAGS;
    memcpy(o.lags, c->lags, sizeof(c->lags));
    o.grid_given = 1;
    o.x_min = c->x_min;
    o.x_max = c->x_max;
    o.n_grid = AENL_DIAGNOSE_N_GRID;
    o.bandwidth = c->bandwidth;
    o.split = 1;
    o.prefilter = 0.0;
    o.lags_auto = 0;
    aenl_curves_t cv;
    const aenl_status_t st = aenl_curves_compute(y, m, &o, &cv, err);
    if (st != AENL_OK)
    {
        return st;
    }
    for (int d = 0; d < 2; ++d)
    {
        for (size_t l = 0; l < AENL_DIAGNOSE_N_LAGS; ++l)
        {
            for (size_t k = 0; k < AENL_DIAGNOSE_N_GRID; ++k)
            {
                const size_t src = aenl_curves_at(&cv, d + 1, l, k);
                const size_t dst =
                    ((size_t)d * AENL_DIAGNOSE_N_LAGS + l) * AENL_DIAGNOSE_N_GRID + k;
                const double w = cv.n_eff[src];
                const int ok = isfinite(cv.mean[src]) && isfinite(cv.var[src]) && w > 0.0;
                s->weight[dst] = ok ? w : 0.0;
                s->mean[dst] = ok ? cv.mean[src] : (double)NAN;
                s->sd[dst] = ok ? sqrt(fmax(cv.var[src], 0.0)) : (double)NAN;
            }
        }
    }
    aenl_curves_free(&cv);
    return AENL_OK;
}

aenl_status_t aenl_diagnose_signature(const double *x, size_t n, const aenl_diagnose_chan_t *c,
                                      aenl_diagnose_sig_t *s, double *psd, aenl_err_t *err)
{
    memset(s, 0, sizeof(*s));
    const double limit = 1e4 * fmax(c->scale, fabs(c->mean));
    for (size_t i = 0; i < n; ++i)
    {
        if (!isfinite(x[i]) || fabs(x[i] - c->mean) > limit)
        {
            return AENL_OK; /* diverged: valid = 0 */
        }
    }
    /* A simulated record that never moves (a model at rest, simulated without noise: the
     * simulations of a noise-free record get none) has no conditional curves; like a diverged
     * one it is no match for the record, which moves (aenl_diagnose_chan_setup rejects a
     * constant one). */
    int moves = 0;
    for (size_t i = 1; i < n && !moves; ++i)
    {
        moves = fabs(x[i] - x[0]) > 0.0;
    }
    if (!moves)
    {
        return AENL_OK; /* valid = 0 */
    }
    if (n <= c->settle + 64u || n - c->settle < c->seg)
    {
        aenl_err_set(err, "record of %zu samples is shorter than the signature needs", n);
        return AENL_E_ARG;
    }
    double *y = lowpass(x, n, c->cutoff);
    const size_t nb = c->seg / 2u + 1u;
    double *p = malloc(nb * sizeof(double));
    if (y == NULL || p == NULL)
    {
        free(y);
        free(p);
        aenl_err_set(err, "out of memory (signature)");
        return AENL_E_DIM;
    }
    const size_t m = n - c->settle;
    const double *ys = y + c->settle;
    /* Envelope: RMS about the measured mean in equal windows. */
    for (size_t w = 0; w < AENL_DIAGNOSE_N_ENV; ++w)
    {
        const size_t a = w * m / AENL_DIAGNOSE_N_ENV, b = (w + 1u) * m / AENL_DIAGNOSE_N_ENV;
        double acc = 0.0;
        for (size_t i = a; i < b; ++i)
        {
            acc += (ys[i] - c->mean) * (ys[i] - c->mean);
        }
        s->env[w] = sqrt(acc / (double)(b > a ? b - a : 1u));
    }
    aenl_status_t st = curves_of(ys, m, c, s, err);
    if (st == AENL_OK)
    {
        double *sorted = malloc(m * sizeof(double));
        if (sorted == NULL)
        {
            aenl_err_set(err, "out of memory (quantiles)");
            st = AENL_E_DIM;
        }
        else
        {
            memcpy(sorted, ys, m * sizeof(double));
            aenl_sort_doubles(sorted, m);
            for (size_t q = 0; q < AENL_DIAGNOSE_N_QUANT; ++q)
            {
                s->quant[q] = aenl_quantile_sorted(sorted, m, aenl_diagnose_quant_p[q]);
            }
            s->amp = 0.5 * (s->quant[AENL_DIAGNOSE_N_QUANT - 1u] - s->quant[0]);
            free(sorted);
        }
    }
    if (st == AENL_OK)
    {
        st = aenl_diagnose_welch(x + c->settle, m, c->seg, p, err);
    }
    if (st == AENL_OK)
    {
        for (size_t b = 0; b < c->n_bands; ++b)
        {
            double acc = 0.0;
            for (size_t k = c->band_lo[b]; k < c->band_hi[b]; ++k)
            {
                acc += p[k];
            }
            acc /= (double)(c->band_hi[b] - c->band_lo[b]);
            s->lpsd[b] = log(fmax(acc, 1e-300));
        }
        s->freq = psd_peak(p, nb, 2u) / (double)c->seg;
        if (psd != NULL)
        {
            memcpy(psd, p, nb * sizeof(double));
        }
        s->valid = 1;
    }
    free(y);
    free(p);
    return st;
}

/* ---- distance ------------------------------------------------------------------------------ */

size_t aenl_diagnose_n_elements(const aenl_diagnose_chan_t *c, aenl_diagnose_family_t f)
{
    switch (f)
    {
        case AENL_DIAGNOSE_AMPLITUDE:
            return AENL_DIAGNOSE_N_QUANT + AENL_DIAGNOSE_N_ENV;
        case AENL_DIAGNOSE_MEAN:
        case AENL_DIAGNOSE_STD:
            return AENL_DIAGNOSE_N_CURVE;
        case AENL_DIAGNOSE_SPECTRUM:
            return c->n_bands;
        default:
            return 0;
    }
}

static double clampd(double v)
{
    return v > AENL_DIAGNOSE_CAP ? AENL_DIAGNOSE_CAP
                                 : (v < -AENL_DIAGNOSE_CAP ? -AENL_DIAGNOSE_CAP : v);
}

double aenl_diagnose_element(const aenl_diagnose_chan_t *c, const aenl_diagnose_sig_t *a,
                             const aenl_diagnose_sig_t *b, aenl_diagnose_family_t f, size_t i,
                             double *w)
{
    *w = 1.0;
    if (!a->valid && !b->valid)
    {
        return 0.0; /* both diverged: they agree */
    }
    if (!a->valid || !b->valid)
    {
        return AENL_DIAGNOSE_CAP;
    }
    switch (f)
    {
        case AENL_DIAGNOSE_AMPLITUDE:
            if (i < AENL_DIAGNOSE_N_QUANT)
            {
                return clampd((a->quant[i] - b->quant[i]) / c->scale);
            }
            return clampd((a->env[i - AENL_DIAGNOSE_N_QUANT] - b->env[i - AENL_DIAGNOSE_N_QUANT]) /
                          c->scale);
        case AENL_DIAGNOSE_MEAN:
        case AENL_DIAGNOSE_STD:
            *w = a->weight[i];
            if (!(a->weight[i] >= AENL_DIAGNOSE_MIN_WEIGHT))
            {
                *w = 0.0;
                return (double)NAN;
            }
            if (!(b->weight[i] >= AENL_DIAGNOSE_MIN_WEIGHT))
            {
                return 1.0; /* the other record never reaches this amplitude */
            }
            return f == AENL_DIAGNOSE_MEAN ? clampd((a->mean[i] - b->mean[i]) / c->scale)
                                           : clampd((a->sd[i] - b->sd[i]) / c->scale);
        case AENL_DIAGNOSE_SPECTRUM:
            return clampd(0.5 * (a->lpsd[i] - b->lpsd[i]));
        default:
            *w = 0.0;
            return (double)NAN;
    }
}

double aenl_diagnose_distance(const aenl_diagnose_chan_t *c, const aenl_diagnose_sig_t *a,
                              const aenl_diagnose_sig_t *b, double fam[AENL_DIAGNOSE_N_FAMILY])
{
    double total = 0.0;
    for (int f = 0; f < AENL_DIAGNOSE_N_FAMILY; ++f)
    {
        const size_t ne = aenl_diagnose_n_elements(c, (aenl_diagnose_family_t)f);
        double sw = 0.0, sd2 = 0.0;
        for (size_t i = 0; i < ne; ++i)
        {
            double w = 0.0;
            const double d = aenl_diagnose_element(c, a, b, (aenl_diagnose_family_t)f, i, &w);
            if (w > 0.0 && isfinite(d))
            {
                sw += w;
                sd2 += w * d * d;
            }
        }
        fam[f] = sw > 0.0 ? sqrt(sd2 / sw) : 0.0;
        total += fam[f] * fam[f];
    }
    return sqrt(total / AENL_DIAGNOSE_N_FAMILY);
}
