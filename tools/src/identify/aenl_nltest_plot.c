/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_nltest_plot.c
 * @brief The figures of the likelihood-based test (aenl_nltest.h): each tested channel's record
 *        with its switching points, and the laws fitted to a channel that rejects.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "aenl_tools/aenl_nltest.h"
#include "aenl_tools/aenl_plot.h"

/* Time-series figure: the whole record as a min/max envelope over at most this many bins, and
 * the last samples at full rate. */
#define TS_BINS   1500u
#define TS_DETAIL 2000u
/* Positions at which the law figure evaluates each law. */
#define LAW_POINTS 301u

/* What every figure of a record shares. */
typedef struct
{
    const char *dir, *path;
    char stem[128];
    const double *time; /* the time column, NULL when the record has none (sample index) */
    const char *t_name;
    size_t n;
    aenl_plot_done_fn done;
    void *done_ctx;
} fig_t;

/* The figure's path (DIR/<stem>_<channel>_<kind>.png) into png, and gnuplot run on it. */
static aenl_status_t draw(const fig_t *f, const char *channel, const char *kind,
                          const aenl_plot_var_t *vars, size_t n_vars, aenl_err_t *err)
{
    char piece[128], png[4096 + 256], script[32];
    aenl_plot_file_piece(channel, piece, sizeof(piece));
    (void)snprintf(png, sizeof(png), "%s/%s_%s_%s.png", f->dir, f->stem, piece, kind);
    (void)snprintf(script, sizeof(script), "identify_%s", kind);
    aenl_status_t st = aenl_plot_run(script, vars, n_vars, png, err);
    if (st == AENL_OK)
    {
        st = f->done(f->done_ctx, png, err); /* a failure is undone when the run ends */
    }
    return st;
}

/* The channel's switching points as a gnuplot word list, and (spans) their intervals. */
static void marks_of(const aenl_nlt_channel_t *c, char *marks, char *spans, size_t n)
{
    size_t lm = 0;
    size_t ls = 0;
    marks[0] = '\0';
    spans[0] = '\0';
    for (size_t k = 0; k < c->n_points && k < AENL_NLT_MAX_POINTS; ++k)
    {
        const int w = snprintf(marks + lm, n - lm, "%s%.10g", k ? " " : "", c->points[k]);
        lm += (w > 0 && (size_t)w < n - lm) ? (size_t)w : 0u;
        const int w2 = snprintf(spans + ls, n - ls, "%s%.10g %.10g", k ? " " : "", c->point_lo[k],
                                c->point_hi[k]);
        ls += (w2 > 0 && (size_t)w2 < n - ls) ? (size_t)w2 : 0u;
    }
}

static void title_of(const fig_t *f, const aenl_nlt_channel_t *c, const char *name,
                     const char *what, char *buf, size_t n)
{
    const char *base = strrchr(f->path, '/') ? strrchr(f->path, '/') + 1 : f->path;
    if (c->nonlinear)
    {
        (void)snprintf(buf, n, "%s: %s, %s (p %.3g; law confidence %.2f) - %s", base, name,
                       aenl_nlt_class_name(c->cls, c->undetermined), c->p, c->confidence, what);
    }
    else
    {
        (void)snprintf(buf, n, "%s: %s, linear (p %.3g) - %s", base, name, c->p, what);
    }
    aenl_plot_text(buf);
}

/* A channel's record as time-series rows: bins of `per` samples, then the last samples. */
typedef struct
{
    const fig_t *f;
    const double *x;
    size_t per, first_det;
} ts_rows_t;

static void ts_row(const void *ctx, int detail, size_t k, double *t, double *lo, double *hi)
{
    const ts_rows_t *r = (const ts_rows_t *)ctx;
    const size_t n = r->f->n;
    const size_t i0 = detail ? r->first_det + k : k * r->per;
    *t = r->f->time != NULL ? r->f->time[i0] : (double)i0;
    if (detail)
    {
        *lo = r->x[i0];
        return;
    }
    *lo = HUGE_VAL;
    *hi = -HUGE_VAL;
    for (size_t i = i0; i < n && i < i0 + r->per; ++i)
    {
        *lo = fmin(*lo, r->x[i]);
        *hi = fmax(*hi, r->x[i]);
    }
}

/* (1) The record: envelope of the whole, the last samples at full rate, switching points. */
static aenl_status_t plot_record(const fig_t *f, const double *x, const aenl_nlt_channel_t *c,
                                 const char *name, aenl_err_t *err)
{
    const size_t n = f->n;
    const size_t per = n > TS_BINS ? (n + TS_BINS - 1u) / TS_BINS : 1u;
    const ts_rows_t rows = {f, x, per, n > TS_DETAIL ? n - TS_DETAIL : 0u};
    char env[64], det[64];
    aenl_status_t st =
        aenl_plot_ts_files(ts_row, &rows, (n + per - 1u) / per, n - rows.first_det, env, det, err);
    if (st != AENL_OK)
    {
        return st;
    }
    char title[600], marks[512], spans[1024], ylabel[300], tlabel[300], label[32];
    title_of(f, c, name, "record", title, sizeof(title));
    marks_of(c, marks, spans, sizeof(marks));
    (void)snprintf(ylabel, sizeof(ylabel), "%s", name);
    aenl_plot_text(ylabel);
    (void)snprintf(tlabel, sizeof(tlabel), "%s", f->time != NULL ? f->t_name : "sample");
    aenl_plot_text(tlabel);
    (void)snprintf(label, sizeof(label), "%zu", per);
    const aenl_plot_var_t vars[] = {{"env", env},      {"detail", det},    {"marks", marks},
                                    {"title", title},  {"ylabel", ylabel}, {"per_bin", label},
                                    {"tlabel", tlabel}};
    st = draw(f, name, "timeseries", vars, sizeof(vars) / sizeof(vars[0]), err);
    (void)remove(env);
    (void)remove(det);
    return st;
}

/* (2) The laws the test fitted, against the channel's position (a channel that rejects). */
static aenl_status_t plot_laws(const fig_t *f, const double *x, const aenl_nlt_channel_t *c,
                               const char *name, size_t best, aenl_err_t *err)
{
    double lo = HUGE_VAL;
    double hi = -HUGE_VAL;
    for (size_t i = 0; i < f->n; ++i)
    {
        lo = fmin(lo, x[i]);
        hi = fmax(hi, x[i]);
    }
    /* A force's straight-line part is the linear model's stiffness and offset, which the test
     * takes as nuisance: each law is drawn less its least-squares line over the record's
     * samples, which leaves the part the law adds. */
    double line[AENL_NLT_N_LAWS][2];
    for (size_t l = 0; l < AENL_NLT_N_LAWS; ++l)
    {
        double s1 = 0.0, su = 0.0, suu = 0.0, sf = 0.0, suf = 0.0;
        for (size_t i = 1; i < f->n; ++i)
        {
            const int dir = (x[i] > x[i - 1u]) - (x[i] < x[i - 1u]);
            const double v = aenl_nlt_law_force(c, (aenl_nlt_law_t)l, x[i], dir);
            if (isfinite(v))
            {
                s1 += 1.0;
                su += x[i];
                suu += x[i] * x[i];
                sf += v;
                suf += x[i] * v;
            }
        }
        const double det = s1 * suu - su * su;
        line[l][1] = det > 0.0 ? (s1 * suf - su * sf) / det : 0.0;
        line[l][0] = s1 > 0.0 ? (sf - line[l][1] * su) / s1 : 0.0;
    }
    char in[64];
    FILE *fi = aenl_plot_tmp_open(in, err);
    if (fi == NULL)
    {
        return AENL_E_IO;
    }
    fprintf(fi, "position,polynomial,freeplay,hyst_rising,hyst_falling\n");
    const aenl_nlt_law_t law[4] = {AENL_NLT_POLYNOMIAL, AENL_NLT_FREEPLAY, AENL_NLT_HYSTERESIS,
                                   AENL_NLT_HYSTERESIS};
    const int dir[4] = {0, 0, 1, -1};
    for (size_t k = 0; k < LAW_POINTS; ++k)
    {
        const double u = lo + (hi - lo) * (double)k / (double)(LAW_POINTS - 1u);
        aenl_plot_put_num(fi, u, ",");
        for (size_t q = 0; q < 4u; ++q)
        {
            const double v = aenl_nlt_law_force(c, law[q], u, dir[q]);
            aenl_plot_put_num(fi, v - line[law[q]][0] - line[law[q]][1] * u, q < 3u ? "," : "\n");
        }
    }
    aenl_status_t st = aenl_plot_tmp_close(fi, in, err);
    if (st == AENL_OK)
    {
        char title[600], marks[512], spans[1024], xlabel[300];
        title_of(f, c, name, "the laws fitted", title, sizeof(title));
        marks_of(c, marks, spans, sizeof(marks));
        (void)snprintf(xlabel, sizeof(xlabel), "%s", name);
        aenl_plot_text(xlabel);
        const aenl_plot_var_t vars[] = {
            {"in", in},       {"best", aenl_nlt_law_name((aenl_nlt_law_t)best)},
            {"marks", marks}, {"spans", spans},
            {"title", title}, {"xlabel", xlabel}};
        st = draw(f, name, "law", vars, sizeof(vars) / sizeof(vars[0]), err);
    }
    (void)remove(in);
    return st;
}

/* The law of the smallest BIC of a channel whose laws were fitted. */
static size_t best_law(const aenl_nlt_channel_t *c)
{
    size_t best = 0;
    for (size_t l = 1; l < AENL_NLT_N_LAWS; ++l)
    {
        best = c->bic[l] < c->bic[best] ? l : best;
    }
    return best;
}

/* Every figure of every tested channel into f->dir (created beforehand). */
static aenl_status_t plot_all(const fig_t *f, const aenl_nlt_result_t *res,
                              const double *const *chan, const char *const *names, size_t nz,
                              aenl_err_t *err)
{
    aenl_status_t st = AENL_OK;
    for (size_t j = 0; j < nz && j < res->n_channels && st == AENL_OK; ++j)
    {
        const aenl_nlt_channel_t *c = &res->ch[j];
        st = plot_record(f, chan[j], c, names[j], err);
        if (st == AENL_OK && c->laws_fitted)
        {
            st = plot_laws(f, chan[j], c, names[j], best_law(c), err);
        }
    }
    return st;
}

aenl_status_t aenl_nlt_plot(const aenl_nlt_result_t *res, const aenl_plot_record_t *rec,
                            const double *const *chan, const char *const *names, size_t nz,
                            const char *dir, aenl_plot_done_fn done, void *done_ctx,
                            aenl_err_t *err)
{
    fig_t f = {dir, rec->path, "", rec->time, rec->time_name, rec->n, done, done_ctx};
    aenl_plot_data_stem(rec->path, f.stem, sizeof(f.stem));
    return plot_all(&f, res, chan, names, nz, err);
}
