/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_identify_test.c
 * @brief `aenl identify` (the test, its default method): the record alone, by the
 *        likelihood-based test of aenl_nltest, its figures drawn by aenl_nlt_plot (argv has been
 *        parsed by cmd_identify.c).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_nltest.h"
#include "aenl_tools/aenl_plot.h"

static const char *const k_cmd = "identify";

/* The columns named in `list` (comma-separated) into in[]; their count, or -1 after the error
 * message. */
static long input_columns(const aenl_table_t *t, const char *path, const char *list, size_t *in)
{
    long n_in = 0;
    const char *p = list;
    if (list[0] == '\0' || list[strlen(list) - 1u] == ',')
    {
        aenl_cli_error(k_cmd, "--input: '%s' is not a list of column names", list);
        return -1;
    }
    while (p != NULL && *p != '\0')
    {
        const char *comma = strchr(p, ',');
        const size_t len = comma != NULL ? (size_t)(comma - p) : strlen(p);
        char name[256];
        if (len == 0 || len >= sizeof(name))
        {
            aenl_cli_error(k_cmd, "--input: '%s' is not a list of column names", list);
            return -1;
        }
        memcpy(name, p, len);
        name[len] = '\0';
        const long c = aenl_table_find(t, name);
        if (c < 0 || aenl_cli_is_time_column(name))
        {
            aenl_cli_error(k_cmd, "%s: --input %s: %s", path, name,
                           c < 0 ? "no such column" : "the time column is not an input");
            return -1;
        }
        for (long k = 0; k < n_in; ++k)
        {
            if (in[k] == (size_t)c)
            {
                aenl_cli_error(k_cmd, "--input: %s named twice", name);
                return -1;
            }
        }
        if (n_in == AENL_NLT_MAX_INPUT)
        {
            aenl_cli_error(k_cmd, "--input: at most %d inputs", AENL_NLT_MAX_INPUT);
            return -1;
        }
        in[n_in++] = (size_t)c;
        p = comma != NULL ? comma + 1 : NULL;
    }
    return n_in;
}

/* Each figure the library writes joins the run's list; when the run fails after it, the run's
 * outputs are undone and the folders it made removed (aenl_cli_figs_rollback). */
static aenl_status_t fig_done(void *ctx, const char *path, aenl_err_t *err)
{
    return aenl_cli_figs_add((aenl_cli_figs_t *)ctx, path, err);
}

/* The record's time column (the first of them), or -1 when it has none. */
static long time_column(const aenl_table_t *t)
{
    for (size_t c = 0; c < t->n_cols; ++c)
    {
        if (aenl_cli_is_time_column(t->names[c]))
        {
            return (long)c;
        }
    }
    return -1;
}

/* The figures of a run into figs (its folder made), the time axis from the record's time
 * column (the sample index without one); 0, or -1 after the message. */
static int figures(const aenl_table_t *t, const char *path, const char *dir,
                   const aenl_nlt_result_t *res, const double *const *chan,
                   const char *const *names, size_t nz, aenl_cli_figs_t *figs)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_plot_record_t rec = {path, t->n_rows, NULL, ""};
    const long tc = time_column(t);
    if (tc >= 0)
    {
        rec.time = t->data + (size_t)tc * t->n_rows;
        rec.time_name = t->names[tc];
    }
    if (aenl_nlt_plot(res, &rec, chan, names, nz, dir, fig_done, figs, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return -1;
    }
    return 0;
}

/* ---- JSON ------------------------------------------------------------------------------------ */

/* The record's sample step in its time column's unit; NaN without a time column (*has_time 0)
 * or with one row. The record has passed aenl_cli_check_record, so its steps are equal. */
static double record_step(const aenl_table_t *t, int *has_time)
{
    const long tc = time_column(t);
    *has_time = tc >= 0;
    if (tc < 0 || t->n_rows < 2u)
    {
        return (double)NAN;
    }
    const double *tv = t->data + (size_t)tc * t->n_rows;
    return (tv[t->n_rows - 1u] - tv[0]) / (double)(t->n_rows - 1u);
}

/* The run's JSON on stdout, with the record's step and, without a time column, the note the
 * table's run prints on stderr; 0, or -1 when memory runs out (nothing written). */
static int print_json(const aenl_table_t *t, const aenl_nlt_result_t *res, const char *const *names,
                      const char *const *in_names, const char *path)
{
    int has_time = 0;
    const double dt = record_step(t, &has_time);
    char note[4096 + 256];
    if (!has_time)
    {
        aenl_cli_no_time_text(path, note, sizeof(note));
    }
    return aenl_nlt_print_json(stdout, res, names, in_names, path, dt, has_time ? NULL : note) ==
                   AENL_OK
               ? 0
               : -1;
}

/* Where the control's columns come from: the record's table (its time column, -1: none, and
 * its inputs' columns) and the channels tested. */
typedef struct
{
    const aenl_table_t *t;
    long time_col; /* -1: none */
    const char *const *names;
    size_t nz;
    const size_t *in;
    size_t n_in;
} control_layout_t;

/* The control record's column names into names (at most 1 + nz + n_in); their count. */
static size_t control_columns(const control_layout_t *l, const char **names)
{
    size_t k = 0;
    if (l->time_col >= 0)
    {
        names[k++] = l->t->names[l->time_col];
    }
    for (size_t j = 0; j < l->nz; ++j)
    {
        names[k++] = l->names[j];
    }
    for (size_t p = 0; p < l->n_in; ++p)
    {
        names[k++] = l->t->names[l->in[p]];
    }
    return k;
}

/* The control's rows (ctl: n x nz, row-major) through w, opened with the columns of
 * control_columns: the time column as recorded, the channels as simulated, the inputs as
 * recorded. The caller commits. */
static aenl_status_t write_control(aenl_csv_writer_t *w, const control_layout_t *l,
                                   const double *ctl, aenl_err_t *err)
{
    const size_t n = l->t->n_rows;
    double row[1 + AENL_NLT_MAX_CH + AENL_NLT_MAX_INPUT];
    aenl_status_t st = AENL_OK;
    for (size_t r = 0; r < n && st == AENL_OK; ++r)
    {
        size_t k = 0;
        if (l->time_col >= 0)
        {
            row[k++] = l->t->data[(size_t)l->time_col * n + r];
        }
        for (size_t j = 0; j < l->nz; ++j)
        {
            row[k++] = ctl[r * l->nz + j];
        }
        for (size_t p = 0; p < l->n_in; ++p)
        {
            row[k++] = l->t->data[l->in[p] * n + r];
        }
        st = aenl_csv_writer_row(w, row, err);
    }
    return st;
}

/* A record read and checked: its table, its inputs' columns, its channels. */
typedef struct
{
    aenl_table_t t;
    size_t in[AENL_NLT_MAX_INPUT];
    long n_in;
    const double *chan[AENL_NLT_MAX_CH];
    const char *names[AENL_NLT_MAX_CH];
    size_t nz;
} loaded_t;

/* The record of path read and checked as req asks into l. 0, or the exit status after the
 * message (the table freed). */
static int load_record(const char *path, const aenl_identify_test_req_t *req, loaded_t *l)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    if (aenl_table_read(path, &l->t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    l->n_in = req->inputs != NULL ? input_columns(&l->t, path, req->inputs, l->in) : 0;
    long only = -1;
    int bad = l->n_in < 0 || (req->channel != NULL &&
                              (only = aenl_cli_pick_channel(k_cmd, &l->t, path, req->channel)) < 0);
    if (!bad && only >= 0 && aenl_cli_is_input(l->in, (size_t)l->n_in, (size_t)only))
    {
        aenl_cli_error(k_cmd, "--channel %s is also an --input", req->channel);
        bad = 1;
    }
    if (!bad && l->t.n_rows == 0)
    {
        aenl_cli_error(k_cmd, "%s: no data rows (header only)", path);
        bad = 1;
    }
    for (long k = 0; !bad && k < l->n_in; ++k)
    {
        /* checked here, where the column has its name: an input has no gap and moves */
        const double *v = aenl_table_col(&l->t, l->in[k]);
        const char *name = l->t.names[l->in[k]];
        int moves = 0;
        for (size_t r = 0; !bad && r < l->t.n_rows; ++r)
        {
            if (isnan(v[r]))
            {
                aenl_cli_error(k_cmd,
                               "%s: --input %s: data row %zu is missing (an input has no gap)",
                               path, name, r + 1u);
                bad = 1;
            }
            moves |= v[r] < v[0] || v[r] > v[0];
        }
        if (!bad && !moves)
        {
            aenl_cli_error(k_cmd, "%s: --input %s is constant", path, name);
            bad = 1;
        }
    }
    bad = bad || aenl_cli_check_record(k_cmd, &l->t, path, only) != 0 ||
          aenl_cli_record_channels(k_cmd, &l->t, path, l->in, (size_t)l->n_in, only,
                                   AENL_NLT_MAX_CH, l->chan, l->names, &l->nz) != 0;
    if (bad)
    {
        aenl_table_free(&l->t);
        return AENL_EXIT_USAGE;
    }
    return 0;
}

/* 0 when the control may be written to ctl_path, else -1 after the message: not standard
 * output (it would run into the table or the JSON), not the record itself. */
static int control_path_ok(const char *ctl_path, const char *path)
{
    struct stat a;
    struct stat b;
    if (strcmp(ctl_path, "-") == 0)
    {
        aenl_cli_error(k_cmd, "--write-control: give a file, not '-' (standard output holds the "
                              "result)");
        return -1;
    }
    if (strcmp(ctl_path, path) == 0 || (stat(ctl_path, &a) == 0 && stat(path, &b) == 0 &&
                                        a.st_dev == b.st_dev && a.st_ino == b.st_ino))
    {
        aenl_cli_error(k_cmd, "--write-control %s: that is the record itself", ctl_path);
        return -1;
    }
    return 0;
}

int aenl_identify_by_test(const char *path, const aenl_identify_test_req_t *req)
{
    if (req->control_path != NULL && control_path_ok(req->control_path, path) != 0)
    {
        return AENL_EXIT_USAGE;
    }
    const int json = req->json;
    const char *plot_dir = req->plot_dir;
    aenl_err_t err;
    aenl_err_clear(&err);
    loaded_t ld;
    memset(&ld, 0, sizeof(ld));
    const int lrc = load_record(path, req, &ld);
    if (lrc != 0)
    {
        return lrc;
    }
    aenl_table_t t = ld.t;
    const size_t *in = ld.in;
    const long n_in = ld.n_in;
    const double *const *chan = ld.chan;
    const char *const *names = ld.names;
    const size_t nz = ld.nz;
    const size_t n = t.n_rows;
    const double *in_cols[AENL_NLT_MAX_INPUT];
    const char *in_names[AENL_NLT_MAX_INPUT];
    for (long k = 0; k < n_in; ++k)
    {
        in_cols[k] = t.data + in[k] * n;
        in_names[k] = t.names[in[k]];
    }
    /* The figures' folder first (a bad one fails before the long part); removed again on any
     * failure. */
    aenl_cli_figs_t figs;
    memset(&figs, 0, sizeof(figs));
    if (plot_dir != NULL && aenl_cli_figs_mkdir(&figs, plot_dir, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        aenl_cli_figs_rollback(&figs);
        aenl_cli_figs_free(&figs);
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    /* The control's file is opened now too (a bad path fails before the long part); it appears
     * only when the whole run succeeds. */
    const control_layout_t lay = {&t, time_column(&t), names, nz, in, (size_t)n_in};
    aenl_csv_writer_t cw;
    memset(&cw, 0, sizeof(cw));
    double *ctl = NULL;
    if (req->control_path != NULL)
    {
        const char *cnames[1 + AENL_NLT_MAX_CH + AENL_NLT_MAX_INPUT];
        const size_t nc = control_columns(&lay, cnames);
        ctl = (double *)malloc(n * nz * sizeof(double));
        if (ctl == NULL ||
            aenl_csv_writer_open(&cw, req->control_path, cnames, nc, &err) != AENL_OK)
        {
            aenl_cli_error(k_cmd, "%s", ctl == NULL ? "out of memory" : err.msg);
            free(ctl);
            aenl_cli_figs_rollback(&figs);
            aenl_cli_figs_free(&figs);
            aenl_table_free(&t);
            return ctl == NULL ? AENL_EXIT_FAIL : AENL_EXIT_USAGE;
        }
    }
    aenl_nlt_opts_t opts;
    aenl_nlt_opts_default(&opts);
    opts.control_record = ctl;
    opts.level = req->level;
    opts.input = n_in > 0 ? in_cols : NULL;
    opts.n_input = (size_t)n_in;
    opts.n_controls = req->n_controls;
    opts.impulsive = req->impulsive;
    aenl_cli_bar_t bar;
    aenl_cli_bar_begin(&bar, k_cmd, "linear controls");
    opts.progress = &bar.progress;
    aenl_nlt_result_t res;
    const aenl_status_t st = aenl_nlt_run_columns(chan, n, nz, &opts, &res, &err);
    aenl_cli_bar_end(&bar);
    int rc = AENL_EXIT_OK;
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s: %s", path, err.msg[0] ? err.msg : aenl_status_str(st));
        rc = st == AENL_E_DIM ? AENL_EXIT_FAIL : AENL_EXIT_USAGE;
    }
    if (rc == AENL_EXIT_OK && plot_dir != NULL &&
        figures(&t, path, plot_dir, &res, chan, names, nz, &figs) != 0)
    {
        rc = AENL_EXIT_USAGE;
    }
    if (ctl != NULL && rc == AENL_EXIT_OK && write_control(&cw, &lay, ctl, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        rc = AENL_EXIT_USAGE;
    }
    if (rc == AENL_EXIT_OK && json)
    {
        if (print_json(&t, &res, names, in_names, path) != 0)
        {
            aenl_cli_error(k_cmd, "out of memory while writing the JSON");
            rc = AENL_EXIT_FAIL;
        }
    }
    else if (rc == AENL_EXIT_OK)
    {
        aenl_nlt_print_table(stdout, &res, names, in_names, path);
        for (size_t i = 0; i < figs.n_files; ++i)
        {
            printf("%s %s\n", i ? "        " : "figures:", figs.files[i]);
        }
    }
    /* the control's file appears only now, after the result: any failure before leaves none */
    if (ctl != NULL && rc == AENL_EXIT_OK && aenl_csv_writer_commit(&cw, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        rc = AENL_EXIT_USAGE;
    }
    if (ctl != NULL && rc != AENL_EXIT_OK)
    {
        aenl_csv_writer_abort(&cw);
    }
    free(ctl);
    if (rc != AENL_EXIT_OK)
    {
        aenl_cli_figs_rollback(&figs); /* all or nothing: no figure, no folder we made */
    }
    aenl_cli_figs_free(&figs);
    aenl_table_free(&t);
    return rc;
}
