/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_identify.c
 * @brief `aenl identify`: its options, and the conditional moments (--method moments,
 *        docs/identify.md) as a thin layer over aenl_identify_run(): the record is streamed
 *        (never loaded whole), checked row by row on the way, and printed by
 *        aenl_identify_print_table or aenl_identify_print_json; --plot's figures are drawn by
 *        aenl_identify_plot. The default method, the test, is cmd_identify_test.c.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl/aenl_classifier.h"
#include "aenl_cli.h"
#include "aenl_tools/aenl_bandwidth.h"
#include "aenl_tools/aenl_identify.h"
#include "aenl_tools/aenl_parallel.h"
#include "aenl_tools/aenl_plot.h"

static const char *const k_cmd = "identify";

static void help(void)
{
    printf("usage: aenl identify DATA.csv [--channel C] [--json] [--plot DIR] [--level A]\n"
           "                     [--input COL[,COL]] [--controls N] [--write-control FILE]\n"
           "                     [--impulsive]\n"
           "       aenl identify DATA.csv --method moments [--channel C] [--json] [--plot DIR]\n"
           "                     [--bandwidth H] [--no-prefilter] [--forced] [--model BASE.ini]\n"
           "       (either form: [--time COL] [--jobs N])\n\n"
           "Tests every channel of a record (or only C) for a structural nonlinearity, names its\n"
           "law (polynomial, hardening or softening; freeplay; hysteresis) with switching points\n"
           "in the channel's units, and names the channel that carries it. Every column is a\n"
           "channel except the time column (t, time, tau or timestamp, with or without a unit, or\n"
           "the one --time COL names: checked finite, increasing and evenly spaced).\n\n"
           "The test (default): a linear state-space model of all channels is fitted by maximum\n"
           "likelihood, and each channel is tested for a law acting as a force, on the Kalman\n"
           "innovations, at family-wise level A (--level, default 0.01; the level is calibrated\n"
           "on noisy stationary records, not yet on free decays and kick trains: see the docs).\n"
           "The laws of a rejecting channel are compared by a test on their per-sample fits\n"
           "(Vuong's, with the record's own variance): the best is named when it beats each\n"
           "other law (confidence 0.9 after Bonferroni), else the class is 'undetermined' and\n"
           "the candidate laws are listed with their p-values; switching points come with 95 %%\n"
           "profile-likelihood intervals (not calibrated: they are often too narrow). The\n"
           "record is held in memory. See docs/identify-test.md\n\n"
           "--json          one JSON object (aenl-identify-test/5; docs/identify-test.md)\n"
           "--plot DIR      per channel, DIR/<file>_<channel>_timeseries.png (the record, the\n"
           "                switching points marked) and, for a channel that rejects,\n"
           "                DIR/<file>_<channel>_law.png: the force each law adds as fitted,\n"
           "                against the channel's position (needs gnuplot)\n"
           "--level A       family-wise level of the test over the channels (default 0.01)\n"
           "--input COL[,COL]  the named columns are a measured excitation (a shaker's force,\n"
           "                a gust vane): they drive the linear model as known inputs and are\n"
           "                not tested; without them a swept or stepped sine is mispredicted\n"
           "                and read as a law\n"
           "--controls N    also test N linear controls: records simulated from the fitted\n"
           "                linear model, driven by the same inputs, with its noise; per\n"
           "                channel, how many reach the record's statistic and the p-value that\n"
           "                gives, and how many are called nonlinear (each control costs about\n"
           "                one more run)\n"
           "--write-control FILE  write one such linear control as a CSV record: the time\n"
           "                column, the channels tested (simulated, in their units) and the\n"
           "                inputs (as recorded); identify it, with or without --input, to see\n"
           "                what a linear structure driven the same way reads\n"
           "--impulsive     the record is driven by impulses (taps, kicks, a rap test): the\n"
           "                linear model is fitted again with them as state jumps, its noise\n"
           "                estimated without them, and the test runs on that model; without it\n"
           "                a train of kicks reads as a law. A single release or rap needs no\n"
           "                option (its one impulse is the start)\n\n");
    printf("--method moments  the conditional-moments classifier instead (docs/identify.md):\n"
           "                the record is streamed, read twice and never held whole. Its own\n"
           "                options (--bandwidth, --no-prefilter, --forced, --model) choose it\n"
           "                when no --method is given. Verdict: the nonlinear channel with the\n"
           "                strongest evidence (confidence: the channel's times its share of that\n"
           "                evidence among the channels with a law); when none is nonlinear,\n"
           "                class linear or insufficient when no channel could be decided\n"
           "--json          (moments) one JSON object (aenl-identify/2): file, rows, verdict\n"
           "                {class, channel, hardening, switch_points, confidence, by_model,\n"
           "                guess}, channels [{name, class, hardening, switch_points,\n"
           "                switch_point_std, confidence, bandwidth, bandwidth_by, period, noise,\n"
           "                lags}], impulses, limit_cycle, model (with --model), notes\n"
           "--plot DIR      (moments) per channel, DIR/<file>_<channel>_{timeseries,moments,\n"
           "                restoring}.png: the record, the conditional mean and variance for\n"
           "                lags 1, 10, 30, and the restoring-force points, switching points\n"
           "                marked (needs gnuplot)\n"
           "--bandwidth H   kernel half-width in channel units for every channel (default: leave-\n"
           "                one-out cross-validation per channel); 'cv' is the default\n"
           "--no-prefilter  no low-pass at 8 / period before the estimates\n"
           "--forced        the motion is forced (a shaker, a stepped sine, a rotor tone): a\n"
           "                sustained oscillation of constant amplitude is not taken for a limit\n"
           "                cycle, which an unforced linear structure cannot have\n"
           "--model BASE.ini  also test the record against a baseline (linear) model of the\n"
           "                test, as `aenl diagnose` does (the model INI of docs/simulate.md: the\n"
           "                model, its initial condition, turbulence or kick train, [run] dt the\n"
           "                record's step): the effect it names, with its fitted switching\n"
           "                points, is the verdict (the record alone's is printed beside it);\n"
           "                when the baseline fits within its noise, or nothing explains the\n"
           "                misfit, the record's own verdict stands. The record is then held in\n"
           "                memory, and the test runs a few hundred simulations of it (seconds\n"
           "                to minutes)\n"
           "--jobs N        (either method) threads, 1..64, for the work that can run at once:\n"
           "                the test's candidate orders, channels and controls, --model's\n"
           "                simulations (default: the processors online); the answer is the\n"
           "                same for any N\n");
}

/* ---- the record, checked on its way to the pipeline ------------------------------------------ */

/* Time columns checked at most (a record has one; a second is checked too, like in moments). */
#define MAX_TIME_COLS 4

/* A source that forwards the CSV source's rows and checks what aenl_cli_check_record checks on a
 * table, row by row: every time column (aenl_cli_is_time_column) finite, strictly increasing and
 * equally spaced,
 * values within +-AENL_CLI_MAX_ABS, at least one finite and two distinct values per channel read,
 * at least one data row. It also counts the rows and keeps the time of the row last read (the
 * first time column, else the row index) for the time-series figure. */
typedef struct
{
    const aenl_identify_source_t *inner;
    const aenl_identify_csv_t *csv; /* while open: csv->csv the reader, csv->row the file row */
    const char *path;
    long channel; /* -1 all, else the only channel checked */
    size_t rows;
    size_t n_time, t_col[MAX_TIME_COLS]; /* time columns of the file */
    double t_prev[MAX_TIME_COLS];
    aenl_time_steps_t steps[MAX_TIME_COLS];
    double t_now;    /* time (or index) of the row last read */
    char t_name[64]; /* name of the first time column ("row" when there is none) */
    size_t *n_finite;
    double *lo, *hi;
    size_t n_rows_total; /* rows of the first complete pass (0 before) */
    int failed;          /* the record itself was at fault: exit 2 */
} checked_t;

static aenl_status_t checked_open(void *ctx, aenl_err_t *err)
{
    checked_t *c = (checked_t *)ctx;
    c->rows = 0;
    for (size_t k = 0; k < c->inner->n_cols; ++k)
    {
        c->n_finite[k] = 0;
        c->lo[k] = HUGE_VAL;
        c->hi[k] = -HUGE_VAL;
    }
    const aenl_status_t st = c->inner->open(c->inner->ctx, err);
    c->failed |= (st != AENL_OK);
    c->n_time = 0;
    memset(c->steps, 0, sizeof(c->steps));
    (void)snprintf(c->t_name, sizeof(c->t_name), "row");
    if (st == AENL_OK)
    {
        const aenl_csv_t *csv = (const aenl_csv_t *)c->csv->csv;
        for (size_t k = 0; k < aenl_csv_n_cols(csv) && c->n_time < MAX_TIME_COLS; ++k)
        {
            if (aenl_cli_is_time_column(aenl_csv_col_name(csv, k)))
            {
                if (c->n_time == 0)
                {
                    (void)snprintf(c->t_name, sizeof(c->t_name), "%s", aenl_csv_col_name(csv, k));
                }
                c->t_col[c->n_time++] = k;
            }
        }
        if (c->n_time == 0 && c->n_rows_total == 0)
        {
            aenl_cli_note_no_time(k_cmd, c->path);
        }
    }
    return st;
}

static int checked_at_end(checked_t *c, aenl_err_t *err)
{
    if (c->rows == 0)
    {
        aenl_err_set(err, "%s: no data rows (header only)", c->path);
        return -1;
    }
    for (size_t k = 0; k < c->inner->n_cols; ++k)
    {
        if (c->channel >= 0 && (size_t)c->channel != k)
        {
            continue;
        }
        if (c->n_finite[k] == 0)
        {
            aenl_err_set(err, "%s, channel %s: no finite sample (%zu samples, all missing)",
                         c->path, c->inner->names[k], c->rows);
            return -1;
        }
        if (!(c->hi[k] > c->lo[k]))
        {
            aenl_err_set(err,
                         "%s, channel %s: constant signal (every sample is %g): nothing to "
                         "identify (name another channel with --channel)",
                         c->path, c->inner->names[k], c->lo[k]);
            return -1;
        }
    }
    if (c->n_rows_total == 0)
    {
        c->n_rows_total = c->rows;
    }
    return 0;
}

/* The time columns of the row just read; 0 or -1 with err set. */
static int check_time(checked_t *c, aenl_err_t *err)
{
    const aenl_csv_t *csv = (const aenl_csv_t *)c->csv->csv;
    c->t_now = (double)(c->rows - 1u);
    for (size_t i = 0; i < c->n_time; ++i)
    {
        const double t = c->csv->row[c->t_col[i]];
        const char *name = aenl_csv_col_name(csv, c->t_col[i]);
        if (aenl_cli_time_value_check(&c->steps[i], t, c->t_prev[i], c->rows, c->path, name, err) !=
            0)
        {
            return -1;
        }
        c->t_prev[i] = t;
        c->t_now = (i == 0) ? t : c->t_now;
    }
    return 0;
}

static int checked_next(void *ctx, double *row, aenl_err_t *err)
{
    checked_t *c = (checked_t *)ctx;
    const int rc = c->inner->next(c->inner->ctx, row, err);
    if (rc < 0)
    {
        c->failed = 1;
        return rc;
    }
    if (rc == 0)
    {
        const int end = checked_at_end(c, err);
        c->failed |= (end != 0);
        return end;
    }
    c->rows++;
    if (check_time(c, err) != 0)
    {
        c->failed = 1;
        return -1;
    }
    for (size_t k = 0; k < c->inner->n_cols; ++k)
    {
        if (c->channel >= 0 && (size_t)c->channel != k)
        {
            continue;
        }
        const double v = row[k];
        if (isnan(v))
        {
            continue;
        }
        if (!(fabs(v) <= AENL_CLI_MAX_ABS))
        {
            aenl_err_set(err,
                         "%s: column '%s', data row %zu: value %g is too large (the limit is "
                         "+-%g)",
                         c->path, c->inner->names[k], c->rows, v, AENL_CLI_MAX_ABS);
            c->failed = 1;
            return -1;
        }
        c->n_finite[k]++;
        c->lo[k] = v < c->lo[k] ? v : c->lo[k];
        c->hi[k] = v > c->hi[k] ? v : c->hi[k];
    }
    return 1;
}

static void checked_close(void *ctx)
{
    const checked_t *c = (const checked_t *)ctx;
    c->inner->close(c->inner->ctx);
}

/* ---- arguments ------------------------------------------------------------------------------- */

typedef struct
{
    const char *data, *channel, *plot_dir, *model;
    int json;
    int by_test;      /* the likelihood-based test (the default), else the conditional moments */
    int method_given; /* --method was given */
    int moments_only; /* an option that only the moments method takes was given */
    double level;     /* --level */
    int level_given;
    const char *input;        /* --input COL[,COL] */
    long controls;            /* --controls N */
    int impulsive;            /* --impulsive */
    const char *control_path; /* --write-control FILE */
    aenl_identify_opts_t opts;
} args_t;

/* An option that takes a value, at argv[*i]: 0 when taken, -1 after printing a usage error, 1
 * when o is not one of them. */
static int parse_value_option(const char *o, int argc, char **argv, int *i, args_t *a)
{
    const char *v = NULL;
    if (strcmp(o, "--method") == 0)
    {
        if ((v = aenl_cli_value(k_cmd, argc, argv, i)) == NULL)
        {
            return -1;
        }
        if (strcmp(v, "test") == 0 || strcmp(v, "moments") == 0)
        {
            a->by_test = v[0] == 't';
            a->method_given = 1;
        }
        else
        {
            aenl_cli_error(k_cmd, "--method: '%s' is not a method (moments or test)", v);
            return -1;
        }
    }
    else if (strcmp(o, "--controls") == 0)
    {
        if ((v = aenl_cli_value(k_cmd, argc, argv, i)) == NULL ||
            aenl_cli_parse_long(k_cmd, "--controls", v, 1, 999, &a->controls) != 0)
        {
            return -1;
        }
    }
    else if (strcmp(o, "--jobs") == 0)
    {
        long jobs = 0;
        if ((v = aenl_cli_value(k_cmd, argc, argv, i)) == NULL ||
            aenl_cli_parse_long(k_cmd, "--jobs", v, 1, AENL_MAX_JOBS, &jobs) != 0)
        {
            return -1;
        }
        aenl_set_jobs((unsigned)jobs);
    }
    else if (strcmp(o, "--write-control") == 0)
    {
        if ((a->control_path = aenl_cli_value(k_cmd, argc, argv, i)) == NULL)
        {
            return -1;
        }
    }
    else if (strcmp(o, "--input") == 0)
    {
        if ((a->input = aenl_cli_value(k_cmd, argc, argv, i)) == NULL)
        {
            return -1;
        }
    }
    else if (strcmp(o, "--time") == 0)
    {
        if ((v = aenl_cli_value(k_cmd, argc, argv, i)) == NULL)
        {
            return -1;
        }
        aenl_cli_set_time_column(v);
    }
    else if (strcmp(o, "--level") == 0)
    {
        if ((v = aenl_cli_value(k_cmd, argc, argv, i)) == NULL ||
            aenl_cli_parse_double(k_cmd, "--level", v, &a->level) != 0)
        {
            return -1;
        }
        a->level_given = 1;
        if (!(a->level > 0.0 && a->level < 0.5))
        {
            aenl_cli_error(k_cmd, "--level: %s is not a test level (0 < level < 0.5)", v);
            return -1;
        }
    }
    else if (strcmp(o, "--channel") == 0)
    {
        if ((a->channel = aenl_cli_value(k_cmd, argc, argv, i)) == NULL)
        {
            return -1;
        }
    }
    else if (strcmp(o, "--model") == 0)
    {
        if ((a->model = aenl_cli_value(k_cmd, argc, argv, i)) == NULL)
        {
            return -1;
        }
        a->moments_only = 1;
    }
    else if (strcmp(o, "--plot") == 0)
    {
        if ((a->plot_dir = aenl_cli_value(k_cmd, argc, argv, i)) == NULL)
        {
            return -1;
        }
        if (a->plot_dir[0] == '\0')
        {
            aenl_cli_error(k_cmd, "--plot: empty folder name");
            return -1;
        }
    }
    else if (strcmp(o, "--bandwidth") == 0)
    {
        if ((v = aenl_cli_value(k_cmd, argc, argv, i)) == NULL)
        {
            return -1;
        }
        a->moments_only = 1;
        if (strcmp(v, "cv") == 0)
        {
            a->opts.bandwidth = 0.0;
        }
        else if (aenl_cli_parse_double(k_cmd, "--bandwidth", v, &a->opts.bandwidth) != 0)
        {
            return -1;
        }
        else if (!(a->opts.bandwidth > 0.0))
        {
            aenl_cli_error(k_cmd, "--bandwidth: %s must be positive (or 'cv')", v);
            return -1;
        }
    }
    else
    {
        return 1;
    }
    return 0;
}

/* The options that only one method takes, and the combinations that do not go together. */
static int check_args(args_t *a)
{
    if (a->data == NULL)
    {
        aenl_cli_error(k_cmd, "no data file (usage: aenl identify DATA.csv [--channel C] [--json] "
                              "[--method test|moments])");
        return -1;
    }
    /* The options that only the moments method takes choose it when no method is named. */
    if (!a->method_given && a->moments_only)
    {
        a->by_test = 0;
    }
    if (strcmp(a->data, "-") == 0 && !a->by_test)
    {
        aenl_cli_error(k_cmd, "the record is read twice: give a file, not '-' (standard input)");
        return -1;
    }
    if (!a->by_test && (a->level_given || a->controls > 0 || a->input != NULL || a->impulsive ||
                        a->control_path != NULL))
    {
        aenl_cli_error(k_cmd, "%s belongs to the test, not to the moments method (%s)",
                       a->level_given            ? "--level"
                       : a->controls > 0         ? "--controls"
                       : a->input != NULL        ? "--input"
                       : a->control_path != NULL ? "--write-control"
                                                 : "--impulsive",
                       a->method_given ? "--method moments"
                                       : "which --model, --bandwidth, --no-prefilter or --forced "
                                         "chose");
        return -1;
    }
    if (a->by_test && a->moments_only)
    {
        aenl_cli_error(k_cmd, "--method test takes --channel, --json, --plot, --level, --input, "
                              "--controls, --write-control and --impulsive only (--model, "
                              "--bandwidth, --no-prefilter and --forced belong to the moments "
                              "method)");
        return -1;
    }
    if (a->model != NULL && a->channel != NULL)
    {
        aenl_cli_error(k_cmd, "--model tests every channel of the model: it does not go with "
                              "--channel");
        return -1;
    }
    if (a->plot_dir != NULL && !aenl_plot_available())
    {
        aenl_cli_error(k_cmd, "--plot needs gnuplot on PATH (Debian: apt-get install gnuplot-nox)");
        return -1;
    }
    return 0;
}

/* 0 to go on, 1 after --help, -1 after printing a usage error. */
static int parse_args(int argc, char **argv, args_t *a)
{
    memset(a, 0, sizeof(*a));
    aenl_identify_opts_default(&a->opts);
    a->level = 0.01;
    a->by_test = 1;
    for (int i = 1; i < argc; ++i)
    {
        const char *o = argv[i];
        if (strcmp(o, "--help") == 0 || strcmp(o, "-h") == 0)
        {
            help();
            return 1;
        }
        if (strcmp(o, "--json") == 0)
        {
            a->json = 1;
            aenl_cli_set_notes(0);
            continue;
        }
        if (strcmp(o, "--no-prefilter") == 0)
        {
            a->opts.prefilter = 0;
            a->moments_only = 1;
            continue;
        }
        if (strcmp(o, "--forced") == 0)
        {
            a->opts.forced = 1;
            a->moments_only = 1;
            continue;
        }
        if (strcmp(o, "--impulsive") == 0)
        {
            a->impulsive = 1;
            continue;
        }
        const int r = parse_value_option(o, argc, argv, &i, a);
        if (r < 0 || (r > 0 && aenl_cli_positional(k_cmd, o, &a->data, "data file") != 0))
        {
            return -1;
        }
    }
    return check_args(a);
}

/* Index of --channel among the source's channels; -1 after printing the error. */
static long find_channel(const aenl_identify_source_t *src, const char *path, const char *name)
{
    for (size_t k = 0; k < src->n_cols; ++k)
    {
        if (strcmp(src->names[k], name) == 0)
        {
            return (long)k;
        }
    }
    char names[512] = "";
    size_t len = 0;
    for (size_t k = 0; k < src->n_cols && len + strlen(src->names[k]) + 3u < sizeof(names); ++k)
    {
        const int w =
            snprintf(names + len, sizeof(names) - len, "%s%s", k ? ", " : "", src->names[k]);
        len += (w > 0) ? (size_t)w : 0u;
    }
    aenl_cli_error(k_cmd, "%s: no channel '%s' (channels: %s)", path, name, names);
    return -1;
}

/* ---- figures --------------------------------------------------------------------------------- */

/* The time of the row the checked source read last, for the time-series figure. */
static double row_time(const void *ctx)
{
    return ((const checked_t *)ctx)->t_now;
}

/* Each figure the library writes joins the run's list, which the command removes again when the
 * run fails after it. */
static aenl_status_t fig_done(void *ctx, const char *path, aenl_err_t *err)
{
    return aenl_cli_figs_add((aenl_cli_figs_t *)ctx, path, err);
}

/* Every figure of every channel into dir, drawn by the library over the checked source (outs
 * lists what was written). */
static aenl_status_t plot_all(const aenl_identify_result_t *r, const aenl_identify_source_t *src,
                              const checked_t *chk, const char *path, const char *dir,
                              aenl_cli_figs_t *outs, aenl_err_t *err)
{
    /* the time column's step, for accelerations per its unit squared */
    const aenl_time_steps_t *ts = &chk->steps[0];
    const double dt =
        chk->n_time > 0 && ts->k > 1u ? (ts->t_prev - ts->t0) / (double)(ts->k - 1u) : 0.0;
    const aenl_identify_plot_record_t rec = {path,        chk->n_rows_total, dt > 0.0 ? dt : 0.0,
                                             chk->t_name, row_time,          chk};
    return aenl_identify_plot(r, src, &rec, dir, fig_done, outs, err);
}

/* ---- the subcommand -------------------------------------------------------------------------- */

/* Run the pipeline over the checked source and print; the exit status. */
/* The model-based test of --model on the whole record: a diagnosis against the baseline, put in
 * place of the record's verdict. Exit status (messages printed). */
static int model_test(const args_t *a, const aenl_sim_model_t *base, const aenl_sim_run_t *run,
                      aenl_identify_result_t *res)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_table_t t;
    if (aenl_table_read(a->data, &t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    if (aenl_cli_check_record(k_cmd, &t, a->data, -1) != 0)
    {
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    aenl_cli_bar_t bar;
    aenl_cli_bar_begin(&bar, k_cmd, "diagnosing against the model");
    const aenl_status_t st =
        aenl_identify_model_test(res, &t, base, run, aenl_cli_time_column(), &bar.progress, &err);
    aenl_cli_bar_end(&bar);
    aenl_table_free(&t);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s (--model %s): %s", a->data, a->model, err.msg);
        return st == AENL_E_DIM ? AENL_EXIT_FAIL : AENL_EXIT_USAGE;
    }
    return AENL_EXIT_OK;
}

static int identify(const args_t *a, aenl_identify_source_t *csv_src)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_identify_opts_t opts = a->opts;
    if (a->channel != NULL && (opts.channel = find_channel(csv_src, a->data, a->channel)) < 0)
    {
        return AENL_EXIT_USAGE;
    }
    aenl_sim_model_t base;
    aenl_sim_run_t base_run;
    if (a->model != NULL && aenl_sim_load_ini(a->model, &base, &base_run, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    const size_t n = csv_src->n_cols;
    checked_t chk;
    memset(&chk, 0, sizeof(chk));
    chk.inner = csv_src;
    chk.csv = (const aenl_identify_csv_t *)csv_src->ctx;
    chk.path = a->data;
    chk.channel = opts.channel;
    chk.n_finite = malloc(n * sizeof(size_t));
    chk.lo = malloc(n * sizeof(double));
    chk.hi = malloc(n * sizeof(double));
    if (chk.n_finite == NULL || chk.lo == NULL || chk.hi == NULL)
    {
        free(chk.n_finite);
        free(chk.lo);
        free(chk.hi);
        aenl_cli_error(k_cmd, "out of memory");
        return AENL_EXIT_FAIL;
    }
    aenl_identify_source_t src = {
        n, csv_src->names, &chk, checked_open, checked_next, checked_close};
    /* The folder first (a bad one fails before the long part); removed again on any failure. */
    aenl_cli_figs_t outs;
    memset(&outs, 0, sizeof(outs));
    if (a->plot_dir != NULL && aenl_cli_figs_mkdir(&outs, a->plot_dir, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        aenl_cli_figs_rollback(&outs);
        aenl_cli_figs_free(&outs);
        free(chk.n_finite);
        free(chk.lo);
        free(chk.hi);
        return AENL_EXIT_USAGE;
    }
    aenl_identify_result_t res;
    memset(&res, 0, sizeof(res));
    const aenl_status_t st = aenl_identify_run(&src, &opts, &res, &err);
    int rc = AENL_EXIT_OK;
    if (st != AENL_OK)
    {
        /* The record at fault (the source, or a channel the pipeline cannot use): 2; memory or a
         * capacity: an internal failure. */
        const int bad_input = chk.failed || (st != AENL_E_IO && st != AENL_E_DIM);
        const char *msg = err.msg[0] ? err.msg : aenl_status_str(st);
        if (strstr(msg, a->data) != NULL)
        {
            aenl_cli_error(k_cmd, "%s", msg);
        }
        else
        {
            aenl_cli_error(k_cmd, "%s: %s", a->data, msg);
        }
        rc = bad_input ? AENL_EXIT_USAGE : AENL_EXIT_FAIL;
    }
    if (rc == AENL_EXIT_OK && a->model != NULL)
    {
        rc = model_test(a, &base, &base_run, &res);
    }
    if (rc == AENL_EXIT_OK && a->plot_dir != NULL &&
        plot_all(&res, &src, &chk, a->data, a->plot_dir, &outs, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        rc = AENL_EXIT_USAGE;
    }
    if (rc == AENL_EXIT_OK)
    {
        if (a->json)
        {
            if (aenl_identify_print_json(stdout, &res, a->data, chk.n_rows_total, a->model) !=
                AENL_OK)
            {
                aenl_cli_error(k_cmd, "out of memory while writing the JSON");
                rc = AENL_EXIT_FAIL;
            }
        }
        else
        {
            aenl_identify_print_table(stdout, &res, a->data, chk.n_rows_total, &opts, a->model);
            for (size_t i = 0; i < outs.n_files; ++i)
            {
                printf("%s %s\n", i ? "        " : "figures:", outs.files[i]);
            }
        }
    }
    if (rc != AENL_EXIT_OK)
    {
        aenl_cli_figs_rollback(&outs); /* all or nothing: no figure, no folder we made */
    }
    aenl_cli_figs_free(&outs);
    if (st == AENL_OK)
    {
        aenl_identify_free(&res);
    }
    free(chk.n_finite);
    free(chk.lo);
    free(chk.hi);
    return rc;
}

/* The conditional moments over the record a->data: streamed, checked, printed; exit status. */
static int by_moments(const args_t *a)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_identify_source_t csv_src;
    aenl_identify_csv_t csv_ctx;
    memset(&csv_src, 0, sizeof(csv_src));
    memset(&csv_ctx, 0, sizeof(csv_ctx));
    if (aenl_identify_csv_source(&csv_src, &csv_ctx, a->data, aenl_cli_time_column(), &err) !=
        AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        aenl_identify_csv_free(&csv_ctx);
        return AENL_EXIT_USAGE;
    }
    int rc = AENL_EXIT_USAGE;
    if (csv_src.n_cols == 0)
    {
        aenl_cli_error(k_cmd, "%s: no data column (only time)", a->data);
    }
    else
    {
        rc = identify(a, &csv_src);
    }
    aenl_identify_csv_free(&csv_ctx);
    return rc;
}

int aenl_identify_by_moments(const char *path, const char *channel,
                             const aenl_identify_opts_t *opts, const char *model, int json,
                             const char *plot_dir)
{
    args_t a;
    memset(&a, 0, sizeof(a));
    a.data = path;
    a.channel = channel;
    a.opts = *opts;
    a.model = model;
    a.json = json;
    a.plot_dir = plot_dir;
    if (json)
    {
        aenl_cli_set_notes(0); /* stdout holds one JSON document; its notes go in it */
    }
    return by_moments(&a);
}

int aenl_cmd_identify(int argc, char **argv)
{
    args_t a;
    const int pa = parse_args(argc, argv, &a);
    if (pa != 0)
    {
        return pa > 0 ? AENL_EXIT_OK : AENL_EXIT_USAGE;
    }
    if (a.by_test)
    {
        const aenl_identify_test_req_t req = {
            a.channel,          a.input,     a.json,     a.level,
            (size_t)a.controls, a.impulsive, a.plot_dir, a.control_path};
        return aenl_identify_by_test(a.data, &req);
    }
    return by_moments(&a);
}
