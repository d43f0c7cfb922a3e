/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_identify_plot.c
 * @brief The figures of the conditional moments (aenl_identify.h): each channel's record, its
 *        conditional mean and variance, and its restoring force.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_tools/aenl_identify.h"
#include "aenl_tools/aenl_plot.h"

/* Time-series figure: whole record as a min/max envelope over at most this many bins, and a
 * detail of the last samples (12 dominant periods, within these limits). */
#define TS_BINS       1500u
#define TS_DETAIL_MIN 400u
#define TS_DETAIL_MAX 4000u

/* Everything one channel's figures need besides its result. */
typedef struct
{
    const char *dir, *stem, *path;
    aenl_plot_done_fn done;
    void *done_ctx;
    double dt;          /* the time column's step (0: the record has none) */
    const char *t_name; /* the time column's name */
} fig_ctx_t;

static aenl_status_t run_plot(const fig_ctx_t *fc, const aenl_identify_channel_t *ch,
                              const char *kind, const aenl_plot_var_t *vars, size_t n_vars,
                              aenl_err_t *err)
{
    char piece[128], png[4096 + 256];
    aenl_plot_file_piece(ch->name, piece, sizeof(piece));
    (void)snprintf(png, sizeof(png), "%s/%s_%s_%s.png", fc->dir, fc->stem, piece, kind);
    char script[32];
    (void)snprintf(script, sizeof(script), "identify_%s", kind);
    aenl_status_t st = aenl_plot_run(script, vars, n_vars, png, err);
    if (st == AENL_OK)
    {
        st = fc->done(fc->done_ctx, png, err); /* a failure is undone when the run ends */
    }
    return st;
}

/* Switching points as "x1 x2 ..." (gnuplot word list). */
static void marks_label(const aenl_classifier_result_t *res, char *buf, size_t n)
{
    size_t len = 0;
    buf[0] = '\0';
    for (unsigned k = 0; k < res->n_switch && k < AENL_CLASSIFIER_MAX_SWITCH && len < n; ++k)
    {
        const int w =
            snprintf(buf + len, n - len, "%s%.10g", k ? " " : "", (double)res->switch_points[k]);
        len += (w > 0) ? (size_t)w : 0u;
    }
}

static void fig_title(const fig_ctx_t *fc, const aenl_identify_channel_t *ch, const char *what,
                      char *buf, size_t n)
{
    const char *base = strrchr(fc->path, '/') ? strrchr(fc->path, '/') + 1 : fc->path;
    (void)snprintf(buf, n, "%s: %s, %s (confidence %.2f) - %s", base, ch->name,
                   aenl_identify_class_label(&ch->res), (double)ch->res.confidence, what);
    aenl_plot_text(buf);
}

/* (2) conditional mean and variance for the display lags: CSV lag,x,mean,var (all pairs). */
static aenl_status_t plot_moments(const fig_ctx_t *fc, const aenl_identify_channel_t *ch,
                                  aenl_err_t *err)
{
    char tmp[64];
    FILE *f = aenl_plot_tmp_open(tmp, err);
    if (f == NULL)
    {
        return AENL_E_IO;
    }
    char lags[AENL_IDENTIFY_DISPLAY_LAGS * 8 + 1] = "";
    size_t len = 0;
    fprintf(f, "lag,x,mean,var\n");
    for (uint16_t l = 0; l < ch->n_display; ++l)
    {
        for (uint16_t g = 0; g < ch->n_grid; ++g)
        {
            const size_t k = (size_t)l * ch->n_grid + g; /* direction 0: all pairs */
            fprintf(f, "%u,", (unsigned)ch->display_lags[l]);
            aenl_plot_put_num(f, ch->x[g], ",");
            aenl_plot_put_num(f, ch->mean[k], ",");
            aenl_plot_put_num(f, ch->var[k], "\n");
        }
        const int w = snprintf(lags + len, sizeof(lags) - len, "%s%u", l ? " " : "",
                               (unsigned)ch->display_lags[l]);
        len += (w > 0 && (size_t)w < sizeof(lags) - len) ? (size_t)w : 0u;
    }
    aenl_status_t st = aenl_plot_tmp_close(f, tmp, err);
    if (st == AENL_OK)
    {
        char title[600], marks[256], xlabel[300];
        fig_title(fc, ch, "conditional mean and variance", title, sizeof(title));
        marks_label(&ch->res, marks, sizeof(marks));
        (void)snprintf(xlabel, sizeof(xlabel), "%s", ch->name);
        aenl_plot_text(xlabel);
        const aenl_plot_var_t vars[] = {
            {"in", tmp}, {"lags", lags}, {"marks", marks}, {"title", title}, {"xlabel", xlabel}};
        st = run_plot(fc, ch, "moments", vars, sizeof(vars) / sizeof(vars[0]), err);
    }
    (void)remove(tmp);
    return st;
}

/* (3) restoring-force points: CSV dir,position,accel (0 all, 1 rising, 2 falling). */
static aenl_status_t plot_restoring(const fig_ctx_t *fc, const aenl_identify_channel_t *ch,
                                    aenl_err_t *err)
{
    char tmp[64];
    FILE *f = aenl_plot_tmp_open(tmp, err);
    if (f == NULL)
    {
        return AENL_E_IO;
    }
    fprintf(f, "dir,position,accel\n");
    for (unsigned d = 0; d < 3u; ++d)
    {
        for (uint16_t g = 0; g < ch->n_grid; ++g)
        {
            const size_t k = (size_t)d * ch->n_grid + g;
            fprintf(f, "%u,", d);
            aenl_plot_put_num(f, ch->position[k], ",");
            /* per sample squared, or per the time column's unit squared */
            const double a = fc->dt > 0.0 ? ch->accel[k] / (fc->dt * fc->dt) : ch->accel[k];
            aenl_plot_put_num(f, a, "\n");
        }
    }
    aenl_status_t st = aenl_plot_tmp_close(f, tmp, err);
    if (st == AENL_OK)
    {
        char title[600], marks[256], xlabel[300];
        fig_title(fc, ch, "restoring force", title, sizeof(title));
        marks_label(&ch->res, marks, sizeof(marks));
        (void)snprintf(xlabel, sizeof(xlabel), "%s", ch->name);
        aenl_plot_text(xlabel);
        char ylabel[400];
        if (fc->dt > 0.0)
        {
            (void)snprintf(ylabel, sizeof(ylabel), "acceleration a(p), %s per %s^2", ch->name,
                           fc->t_name);
        }
        else
        {
            (void)snprintf(ylabel, sizeof(ylabel), "acceleration a(p), %s per sample^2", ch->name);
        }
        aenl_plot_text(ylabel);
        const aenl_plot_var_t vars[] = {{"in", tmp},
                                        {"marks", marks},
                                        {"title", title},
                                        {"xlabel", xlabel},
                                        {"ylabel", ylabel}};
        st = run_plot(fc, ch, "restoring", vars, sizeof(vars) / sizeof(vars[0]), err);
    }
    (void)remove(tmp);
    return st;
}

/* (1) The time series of every channel, read again from the file with bounded memory: a min/max
 * envelope over at most TS_BINS bins of the whole record, and the last `detail` rows. */
typedef struct
{
    size_t n_bins, per_bin, detail, n_ch;
    const long *col;    /* n_ch source columns */
    double *bin_t;      /* n_bins: time of the bin's first row */
    double *lo, *hi;    /* [n_ch][n_bins] */
    double *det;        /* ring of detail rows x (1 + n_ch): time then the channels */
    size_t n_det;       /* rows in the ring (<= detail) */
    size_t ring_start;  /* slot of the oldest row */
    const char *t_name; /* x-axis label */
} ts_view_t;

static void ts_view_free(ts_view_t *v)
{
    free(v->bin_t);
    free(v->lo);
    free(v->hi);
    free(v->det);
    memset(v, 0, sizeof(*v));
}

static aenl_status_t ts_view_read(ts_view_t *v, const aenl_identify_source_t *src,
                                  const aenl_identify_plot_record_t *rec, aenl_err_t *err)
{
    const size_t n_rows = rec->n_rows;
    if (n_rows == 0 || v->n_ch == 0 || v->detail == 0)
    {
        aenl_err_set(err, "no data rows to plot");
        return AENL_E_ARG;
    }
    v->n_bins = n_rows < TS_BINS ? n_rows : TS_BINS;
    v->per_bin = (n_rows + v->n_bins - 1u) / v->n_bins;
    v->n_bins = (n_rows + v->per_bin - 1u) / v->per_bin;
    v->bin_t = malloc(v->n_bins * sizeof(double));
    v->lo = malloc(v->n_ch * v->n_bins * sizeof(double));
    v->hi = malloc(v->n_ch * v->n_bins * sizeof(double));
    v->det = malloc(v->detail * (1u + v->n_ch) * sizeof(double));
    double *row = malloc((src->n_cols + 1u) * sizeof(double));
    if (v->bin_t == NULL || v->lo == NULL || v->hi == NULL || v->det == NULL || row == NULL)
    {
        free(row);
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    for (size_t b = 0; b < v->n_bins; ++b)
    {
        v->bin_t[b] = (double)NAN; /* a bin left empty (the file shrank) is not drawn */
    }
    for (size_t k = 0; k < v->n_ch * v->n_bins; ++k)
    {
        v->lo[k] = HUGE_VAL;
        v->hi[k] = -HUGE_VAL;
    }
    aenl_status_t st = src->open(src->ctx, err);
    size_t r = 0;
    int rc = 1;
    while (st == AENL_OK && (rc = src->next(src->ctx, row, err)) == 1 && r < n_rows)
    {
        const double t = rec->row_time(rec->time_ctx); /* the time of this row */
        const size_t b = r / v->per_bin;
        if (r % v->per_bin == 0u)
        {
            v->bin_t[b] = t;
        }
        double *d = v->det + (r % v->detail) * (1u + v->n_ch);
        d[0] = t;
        for (size_t c = 0; c < v->n_ch; ++c)
        {
            const double x = row[v->col[c]];
            d[1u + c] = x;
            if (!isnan(x))
            {
                v->lo[c * v->n_bins + b] = fmin(v->lo[c * v->n_bins + b], x);
                v->hi[c * v->n_bins + b] = fmax(v->hi[c * v->n_bins + b], x);
            }
        }
        r++;
    }
    if (st == AENL_OK)
    {
        src->close(src->ctx);
        if (rc < 0)
        {
            st = AENL_E_IO; /* err set by the source */
        }
    }
    v->n_det = r < v->detail ? r : v->detail;
    v->ring_start = r < v->detail ? 0u : r % v->detail;
    v->t_name = rec->t_name;
    free(row);
    return st;
}

/* Channel c of the view as time-series rows (aenl_plot_ts_row_fn). */
typedef struct
{
    const ts_view_t *v;
    size_t c;
} ts_rows_t;

static void ts_row(const void *ctx, int detail, size_t k, double *t, double *lo, double *hi)
{
    const ts_rows_t *r = (const ts_rows_t *)ctx;
    const ts_view_t *v = r->v;
    if (detail)
    {
        const double *d = v->det + ((v->ring_start + k) % v->detail) * (1u + v->n_ch);
        *t = d[0];
        *lo = d[1u + r->c];
        return;
    }
    *t = v->bin_t[k];
    *lo = v->lo[r->c * v->n_bins + k];
    *hi = v->hi[r->c * v->n_bins + k];
}

static aenl_status_t plot_timeseries(const fig_ctx_t *fc, const ts_view_t *v, size_t c,
                                     const aenl_identify_channel_t *ch, aenl_err_t *err)
{
    char env[64], det[64];
    const ts_rows_t rows = {v, c};
    aenl_status_t st = aenl_plot_ts_files(ts_row, &rows, v->n_bins, v->n_det, env, det, err);
    if (st != AENL_OK)
    {
        return st;
    }
    char title[600], marks[256], ylabel[300], label[128], tlabel[128];
    fig_title(fc, ch, "record", title, sizeof(title));
    marks_label(&ch->res, marks, sizeof(marks));
    (void)snprintf(ylabel, sizeof(ylabel), "%s", ch->name);
    aenl_plot_text(ylabel);
    (void)snprintf(label, sizeof(label), "%zu", v->per_bin);
    (void)snprintf(tlabel, sizeof(tlabel), "%s", v->t_name != NULL ? v->t_name : "row");
    aenl_plot_text(tlabel);
    const aenl_plot_var_t vars[] = {{"env", env},      {"detail", det},    {"marks", marks},
                                    {"title", title},  {"ylabel", ylabel}, {"per_bin", label},
                                    {"tlabel", tlabel}};
    st = run_plot(fc, ch, "timeseries", vars, sizeof(vars) / sizeof(vars[0]), err);
    (void)remove(env);
    (void)remove(det);
    return st;
}

aenl_status_t aenl_identify_plot(const aenl_identify_result_t *r, const aenl_identify_source_t *src,
                                 const aenl_identify_plot_record_t *rec, const char *dir,
                                 aenl_plot_done_fn done, void *done_ctx, aenl_err_t *err)
{
    char stem[128];
    aenl_plot_data_stem(rec->path, stem, sizeof(stem));
    const fig_ctx_t fc = {
        dir, stem, rec->path, done, done_ctx, rec->dt > 0.0 ? rec->dt : 0.0, rec->t_name};
    ts_view_t v;
    memset(&v, 0, sizeof(v));
    long *col = malloc((r->n_channels + 1u) * sizeof(long));
    if (col == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    double period = 0.0;
    for (size_t i = 0; i < r->n_channels; ++i)
    {
        col[i] = 0;
        for (size_t k = 0; k < src->n_cols; ++k)
        {
            col[i] = strcmp(src->names[k], r->ch[i].name) == 0 ? (long)k : col[i];
        }
        period = fmax(period, r->ch[i].period);
    }
    v.n_ch = r->n_channels;
    v.col = col;
    const double want = fmin(fmax(12.0 * period, (double)TS_DETAIL_MIN), (double)TS_DETAIL_MAX);
    v.detail = (size_t)want;
    v.detail = v.detail < rec->n_rows ? v.detail : rec->n_rows;
    aenl_status_t st = ts_view_read(&v, src, rec, err);
    for (size_t i = 0; st == AENL_OK && i < r->n_channels; ++i)
    {
        st = plot_timeseries(&fc, &v, i, &r->ch[i], err);
        if (st == AENL_OK)
        {
            st = plot_moments(&fc, &r->ch[i], err);
        }
        if (st == AENL_OK)
        {
            st = plot_restoring(&fc, &r->ch[i], err);
        }
    }
    ts_view_free(&v);
    free(col);
    return st;
}
