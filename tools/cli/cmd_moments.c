/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_moments.c
 * @brief `aenl moments`: conditional mean/variance curves of one channel (paper Figs. 5-9).
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_bandwidth.h"
#include "aenl_tools/aenl_curves.h"
#include "aenl_tools/aenl_plot.h"

static const char *const k_cmd = "moments";

static void help(void)
{
    printf(
        "usage: aenl moments DATA.csv [--channel C] [--lags 1,10,30] [--grid MIN:MAX:N]\n"
        "                    [--bandwidth cv|H] [--direction all|rising|falling] [--no-split]\n"
        "                    [--forgetting LAMBDA] [-o out.csv] [--plot out.png]\n"
        "                    [--prefilter auto|off|F] [--lags auto] [--expansion exp.csv]\n"
        "                    [--plot-expansion exp.png] [--time COL]\n\n"
        "Kernel estimates of E(X_n | X_{n-L} = x) and Var(X_n | X_{n-L} = x) on a grid, for each\n"
        "lag L (the paper's j = -L). CSV columns: lag,x,mean,var,n_eff,se (after '#' lines that\n"
        "give the source, the bandwidth and how it was chosen). Without -o the CSV goes to "
        "stdout.\n"
        "Defaults: lags 1,10,30; grid over the 0.1%%..99.9%% quantiles with 64 nodes; bandwidth\n"
        "by leave-one-out cross-validation; rising/falling accumulated separately.\n\n"
        "--prefilter auto|F  4th-order Butterworth low-pass first: cutoff F of the sample rate, "
        "or\n"
        "                    auto = 8 / period (period from mean crossings, at most 0.4)\n"
        "--lags auto         geometric lags 1 .. max(5, period/8), as the expansion needs\n"
        "--expansion FILE    per node and direction, the fit m_L = p + v L + a L^2/2 + ...:\n"
        "                    dir,x,position,velocity,accel,se_position,se_velocity,se_accel\n"
        "                    (dir 0 all, 1 rising, 2 falling; per sample units); accel against\n"
        "                    position is the restoring-force curve (needs >= 3 lags)\n"
        "--plot-expansion F  figure of it: acceleration and velocity against position\n"
        "--time COL          the time column is COL (default: the one named t, time, tau or\n"
        "                    timestamp, alone or with a unit)\n");
}

/* What the command line asks for: the record, the channel, the estimator's options and the outputs
 * (NULL when not asked for). */
typedef struct moments_args
{
    const char *data, *channel, *out, *plot, *expansion, *plot_expansion, *time_column;
    int dir; /* aenl_dir_t of the curves written */
    aenl_curves_opts_t o;
} moments_args_t;

/* The parser of an option's value: 0, or -1 after printing what is wrong. */
typedef int (*value_parser_t)(const char *v, moments_args_t *a);

static int parse_grid(const char *s, moments_args_t *a)
{
    aenl_curves_opts_t *o = &a->o;
    char buf[256];
    const size_t len = strlen(s);
    if (len >= sizeof(buf))
    {
        aenl_cli_error(k_cmd, "--grid: value too long");
        return -1;
    }
    memcpy(buf, s, len + 1u);
    char *lo = buf;
    char *hi = strchr(lo, ':');
    char *n_text = hi ? strchr(hi + 1, ':') : NULL;
    if (hi == NULL || n_text == NULL)
    {
        aenl_cli_error(k_cmd, "--grid: '%s' is not MIN:MAX:N", s);
        return -1;
    }
    *hi++ = '\0';
    *n_text++ = '\0';
    long n = 0;
    if (aenl_cli_parse_double(k_cmd, "--grid MIN", lo, &o->x_min) != 0 ||
        aenl_cli_parse_double(k_cmd, "--grid MAX", hi, &o->x_max) != 0 ||
        aenl_cli_parse_long(k_cmd, "--grid N", n_text, 3, AENL_MOMENTS_MAX_GRID, &n) != 0)
    {
        return -1;
    }
    if (!(o->x_max > o->x_min))
    {
        aenl_cli_error(k_cmd, "--grid: MAX (%g) must be above MIN (%g)", o->x_max, o->x_min);
        return -1;
    }
    o->n_grid = (uint16_t)n;
    o->grid_given = 1;
    return 0;
}

static int parse_lags(const char *v, moments_args_t *a)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    if (strcmp(v, "auto") == 0)
    {
        a->o.lags_auto = 1;
    }
    else if (aenl_curves_parse_lags(v, &a->o, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return -1;
    }
    return 0;
}

static int parse_prefilter(const char *v, moments_args_t *a)
{
    if (strcmp(v, "auto") == 0)
    {
        a->o.prefilter = -1.0;
    }
    else if (strcmp(v, "off") == 0)
    {
        a->o.prefilter = 0.0;
    }
    else if (aenl_cli_parse_double(k_cmd, "--prefilter", v, &a->o.prefilter) != 0)
    {
        return -1;
    }
    else if (!(a->o.prefilter > 0.0 && a->o.prefilter < 0.5))
    {
        aenl_cli_error(k_cmd, "--prefilter: %s is not auto, off or a cutoff in (0, 0.5)", v);
        return -1;
    }
    return 0;
}

static int parse_bandwidth(const char *v, moments_args_t *a)
{
    if (strcmp(v, "cv") == 0)
    {
        a->o.bandwidth = 0.0;
    }
    else if (aenl_cli_parse_double(k_cmd, "--bandwidth", v, &a->o.bandwidth) != 0)
    {
        return -1;
    }
    else if (!(a->o.bandwidth > 0.0))
    {
        aenl_cli_error(k_cmd, "--bandwidth: %s must be positive (or 'cv')", v);
        return -1;
    }
    return 0;
}

static int parse_direction(const char *v, moments_args_t *a)
{
    if (strcmp(v, "all") == 0)
    {
        a->dir = AENL_DIR_ALL;
    }
    else if (strcmp(v, "rising") == 0)
    {
        a->dir = AENL_DIR_RISING;
    }
    else if (strcmp(v, "falling") == 0)
    {
        a->dir = AENL_DIR_FALLING;
    }
    else
    {
        aenl_cli_error(k_cmd, "--direction: '%s' is not all, rising or falling", v);
        return -1;
    }
    return 0;
}

static int parse_forgetting(const char *v, moments_args_t *a)
{
    if (aenl_cli_parse_double(k_cmd, "--forgetting", v, &a->o.forgetting) != 0)
    {
        return -1;
    }
    if (!(a->o.forgetting >= AENL_MOMENTS_MIN_FORGETTING) || a->o.forgetting > 1.0)
    {
        aenl_cli_error(k_cmd, "--forgetting: %s is outside [%g, 1]", v,
                       AENL_MOMENTS_MIN_FORGETTING);
        return -1;
    }
    return 0;
}

/* Where the value of option `name` is kept as given; NULL when `name` is not such an option. */
static const char **text_option(const char *name, moments_args_t *a)
{
    if (strcmp(name, "--channel") == 0)
    {
        return &a->channel;
    }
    if (strcmp(name, "--expansion") == 0)
    {
        return &a->expansion;
    }
    if (strcmp(name, "--plot-expansion") == 0)
    {
        return &a->plot_expansion;
    }
    if (strcmp(name, "-o") == 0 || strcmp(name, "--output") == 0)
    {
        return &a->out;
    }
    if (strcmp(name, "--plot") == 0)
    {
        return &a->plot;
    }
    if (strcmp(name, "--time") == 0)
    {
        return &a->time_column;
    }
    return NULL;
}

/* The parser of option `name`'s value; NULL when `name` is not such an option. */
static value_parser_t value_option(const char *name)
{
    static const struct
    {
        const char *name;
        value_parser_t parse;
    } options[] = {{"--lags", parse_lags},           {"--prefilter", parse_prefilter},
                   {"--grid", parse_grid},           {"--bandwidth", parse_bandwidth},
                   {"--direction", parse_direction}, {"--forgetting", parse_forgetting}};
    for (size_t k = 0; k < sizeof(options) / sizeof(options[0]); ++k)
    {
        if (strcmp(name, options[k].name) == 0)
        {
            return options[k].parse;
        }
    }
    return NULL;
}

/* Option argv[*i] (and its value, advancing *i): 1 when taken, 0 when it is not an option of the
 * command, -1 after printing what is wrong. */
static int parse_option(int argc, char **argv, int *i, moments_args_t *a)
{
    const char *name = argv[*i];
    if (strcmp(name, "--no-split") == 0)
    {
        a->o.split = 0;
        return 1;
    }
    const char **text = text_option(name, a);
    const value_parser_t parse = value_option(name);
    if (text == NULL && parse == NULL)
    {
        return 0;
    }
    const char *v = aenl_cli_value(k_cmd, argc, argv, i);
    if (v == NULL)
    {
        return -1;
    }
    if (text != NULL)
    {
        *text = v;
        return 1;
    }
    return parse(v, a) == 0 ? 1 : -1;
}

/* 0 to go on, 1 after the help, -1 after printing what is wrong. */
static int parse_args(int argc, char **argv, moments_args_t *a)
{
    memset(a, 0, sizeof(*a));
    a->dir = AENL_DIR_ALL;
    aenl_curves_opts_default(&a->o);
    for (int i = 1; i < argc; ++i)
    {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
        {
            help();
            return 1;
        }
        const int taken = parse_option(argc, argv, &i, a);
        if (taken < 0 ||
            (taken == 0 && aenl_cli_positional(k_cmd, argv[i], &a->data, "data file") != 0))
        {
            return -1;
        }
    }
    aenl_cli_set_time_column(a->time_column);
    return 0;
}

/* The checks that need the whole command line: 0, or -1 after printing what is wrong. */
static int check_args(const moments_args_t *a)
{
    if (a->data == NULL)
    {
        aenl_cli_error(k_cmd, "no data file (usage: aenl moments DATA.csv --channel C ...)");
        return -1;
    }
    if (a->dir != AENL_DIR_ALL && !a->o.split)
    {
        aenl_cli_error(k_cmd, "--direction %s needs the direction split (drop --no-split)",
                       a->dir == AENL_DIR_RISING ? "rising" : "falling");
        return -1;
    }
    if ((a->expansion != NULL || a->plot_expansion != NULL) && !a->o.lags_auto && a->o.n_lags < 3u)
    {
        aenl_cli_error(k_cmd, "--expansion needs at least 3 lags (--lags auto or a list)");
        return -1;
    }
    if ((a->plot != NULL || a->plot_expansion != NULL) && !aenl_plot_available())
    {
        aenl_cli_error(k_cmd, "--plot needs gnuplot on PATH (Debian: apt-get install gnuplot-nox)");
        return -1;
    }
    return 0;
}

/* A fresh name /tmp/aenl_<stem>_XXXXXX for a figure's data, into buf[64]. The file mkstemp makes
 * is removed again at once: written through an output file, a name that exists is a file the run
 * replaces, which a failed run would put back; a new one it removes. */
static aenl_status_t make_tmp(char buf[64], const char *stem, aenl_err_t *err)
{
    (void)snprintf(buf, 64, "/tmp/aenl_%s_XXXXXX", stem);
    const int fd = mkstemp(buf);
    if (fd < 0)
    {
        buf[0] = '\0';
        aenl_err_set(err, "cannot create a temporary file in /tmp");
        return AENL_E_IO;
    }
    (void)close(fd);
    (void)unlink(buf);
    return AENL_OK;
}

/* The expansion CSV (to `path`, or a temporary file when only its figure is asked for) and its
 * figure; nothing is left behind on failure. */
static aenl_status_t write_expansion(const aenl_curves_t *c, const char *data, const char *chan,
                                     const char *path, const char *png, aenl_err_t *err)
{
    char tmp[64] = "";
    const char *csv = path;
    if (csv == NULL)
    {
        if (make_tmp(tmp, "expansion", err) != AENL_OK)
        {
            return AENL_E_IO;
        }
        csv = tmp;
    }
    aenl_status_t st = aenl_curves_write_expansion_csv(c, data, chan, csv, err);
    if (st == AENL_OK && png != NULL)
    {
        char title[600];
        const char *base = strrchr(data, '/') ? strrchr(data, '/') + 1 : data;
        (void)snprintf(title, sizeof(title), "%s: %s, lag expansion (order %u, prefilter %.3g)",
                       base, chan, (unsigned)c->taylor_order, c->prefilter);
        for (char *p = title; *p; ++p)
        {
            *p = (char)((*p == '\'' || *p == '\n') ? ' ' : *p);
        }
        const aenl_plot_var_t vars[] = {{"in", csv}, {"title", title}, {"xlabel", chan}};
        /* on failure the CSV written above is undone when the run ends */
        st = aenl_plot_run("expansion", vars, sizeof(vars) / sizeof(vars[0]), png, err);
    }
    if (tmp[0] != '\0')
    {
        (void)remove(tmp);
    }
    return st;
}

/* The record and its checked column; chan[256] gets the column's name. 0, or -1 after printing
 * what is wrong (the table then freed). */
static int read_record(const moments_args_t *a, aenl_table_t *t, long *col, char chan[256])
{
    aenl_err_t err;
    aenl_err_clear(&err);
    if (aenl_table_read(a->data, t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return -1;
    }
    *col = aenl_cli_pick_channel(k_cmd, t, a->data, a->channel);
    if (*col < 0 || aenl_cli_check_record(k_cmd, t, a->data, *col) != 0)
    {
        aenl_table_free(t);
        return -1;
    }
    (void)snprintf(chan, 256, "%s", t->names[*col]); /* a label: truncation is fine */
    if (t->n_rows == 0)
    {
        aenl_cli_error(k_cmd, "%s: no data rows (header only)", a->data);
        aenl_table_free(t);
        return -1;
    }
    return 0;
}

/* The curves of the record's channel, named into chan[256]. 0, or -1 after printing what is
 * wrong. */
static int compute_curves(const moments_args_t *a, aenl_curves_t *c, char chan[256],
                          aenl_err_t *err)
{
    aenl_table_t t;
    long col = 0;
    if (read_record(a, &t, &col, chan) != 0)
    {
        return -1;
    }
    const double *x = aenl_table_col(&t, (size_t)col);
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; a->o.grid_given && i < t.n_rows; ++i) /* a pass only for a given grid */
    {
        lo = isnan(x[i]) ? lo : fmin(lo, x[i]);
        hi = isnan(x[i]) ? hi : fmax(hi, x[i]);
    }
    if (a->o.grid_given && (a->o.x_max < lo || a->o.x_min > hi))
    {
        /* no node could hold a sample: every estimate would be NaN (the library computes such
         * curves, which diagnose compares; asked for on the command line, they are a mistake) */
        aenl_cli_error(
            k_cmd, "%s, channel %s: --grid [%g, %g] holds none of the samples (they span [%g, %g])",
            a->data, chan, a->o.x_min, a->o.x_max, lo, hi);
        aenl_table_free(&t);
        return -1;
    }
    const aenl_status_t st = aenl_curves_compute(x, t.n_rows, &a->o, c, err);
    aenl_table_free(&t);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s, channel %s: %s", a->data, chan, err->msg);
        return -1;
    }
    return 0;
}

/* 1 when the CSV goes to a file ("-" and no -o are standard output). */
static int out_is_file(const char *out)
{
    return out != NULL && strcmp(out, "-") != 0;
}

/* The figure of the curves, from the CSV at csv_path (when it fails, the run's end undoes the
 * CSV already written: no CSV without its requested figure). */
static aenl_status_t plot_moments(const moments_args_t *a, const aenl_curves_t *c, const char *chan,
                                  const char *csv_path, aenl_err_t *err)
{
    /* Up to AENL_MOMENTS_MAX_LAGS lags of up to 4 digits and a space each: a bounded append. */
    char lags[AENL_MOMENTS_MAX_LAGS * 6 + 1] = "";
    size_t lags_len = 0;
    for (uint16_t i = 0; i < c->n_lags && lags_len < sizeof(lags); ++i)
    {
        const int w = snprintf(lags + lags_len, sizeof(lags) - lags_len, "%s%u", i ? " " : "",
                               (unsigned)c->lags[i]);
        lags_len += (w > 0) ? (size_t)w : 0u;
    }
    char title[600];
    const char *base = strrchr(a->data, '/') ? strrchr(a->data, '/') + 1 : a->data;
    (void)snprintf(title, sizeof(title), "%s: %s (h = %.3g, %s)", base, chan, c->bandwidth,
                   a->dir == AENL_DIR_ALL      ? "all pairs"
                   : a->dir == AENL_DIR_RISING ? "rising"
                                               : "falling");
    for (char *p = title; *p; ++p)
    {
        *p = (char)((*p == '\'' || *p == '\n') ? ' ' : *p);
    }
    const aenl_plot_var_t vars[] = {
        {"in", csv_path}, {"lags", lags}, {"title", title}, {"xlabel", chan}};
    return aenl_plot_run("moments", vars, sizeof(vars) / sizeof(vars[0]), a->plot, err);
}

/* The curves' CSV (to the output file or standard output) and its figure. The figure needs the
 * CSV on disk: the output file, or a temporary one when the CSV goes to standard output. */
static aenl_status_t write_curves(const moments_args_t *a, const aenl_curves_t *c, const char *chan,
                                  aenl_err_t *err)
{
    aenl_status_t st = AENL_OK;
    char tmp_csv[64] = "";
    const char *csv_path = a->out;
    if (a->plot != NULL && !out_is_file(a->out))
    {
        st = make_tmp(tmp_csv, "moments", err);
        if (st == AENL_OK)
        {
            st = aenl_curves_write_csv(c, a->dir, a->data, chan, tmp_csv, err);
            csv_path = tmp_csv;
        }
    }
    if (st == AENL_OK && !out_is_file(a->out) && a->plot == NULL)
    {
        st = aenl_curves_write_csv(c, a->dir, a->data, chan, NULL, err);
    }
    else if (st == AENL_OK && out_is_file(a->out))
    {
        st = aenl_curves_write_csv(c, a->dir, a->data, chan, a->out, err);
    }
    if (st == AENL_OK && a->plot != NULL)
    {
        st = plot_moments(a, c, chan, csv_path, err);
    }
    if (tmp_csv[0] != '\0')
    {
        (void)remove(tmp_csv);
    }
    return st;
}

/* The lag expansion and its figure (when they fail, the run's end undoes the CSV and figure
 * already written: all or nothing). */
static aenl_status_t write_expansion_outputs(const moments_args_t *a, const aenl_curves_t *c,
                                             const char *chan, aenl_err_t *err)
{
    return write_expansion(c, a->data, chan, a->expansion, a->plot_expansion, err);
}

/* The summary on standard output, when the CSV went to a file. */
static void print_summary(const moments_args_t *a, const aenl_curves_t *c, const char *chan)
{
    printf("%s: channel %s, %zu samples (%zu missing), lags", a->data, chan, c->n_samples,
           c->n_missing);
    for (uint16_t i = 0; i < c->n_lags; ++i)
    {
        printf("%s%u", i ? "," : " ", (unsigned)c->lags[i]);
    }
    printf(", grid [%.6g, %.6g] x %u, bandwidth %.6g (%s) -> %s%s%s\n", c->x[0],
           c->x[c->n_grid - 1u], (unsigned)c->n_grid, c->bandwidth,
           c->bw_method < 0 ? "given" : aenl_bw_method_str(c->bw_method), a->out,
           a->plot ? ", " : "", a->plot ? a->plot : "");
    if (c->period > 0.0 || c->prefilter > 0.0)
    {
        printf("  period %.4g samples, pre-filter cutoff %.4g of the sample rate\n", c->period,
               c->prefilter);
    }
    if (c->cv_samples > 0u && c->cv_samples < c->n_samples)
    {
        printf("  bandwidth chosen on the first %zu samples and scaled to the record by "
               "(%zu / %zu)^(1/5)\n",
               c->cv_samples, c->cv_samples, c->n_samples);
    }
}

int aenl_cmd_moments(int argc, char **argv)
{
    moments_args_t a;
    const int pr = parse_args(argc, argv, &a);
    if (pr != 0)
    {
        return pr > 0 ? AENL_EXIT_OK : AENL_EXIT_USAGE;
    }
    if (check_args(&a) != 0)
    {
        return AENL_EXIT_USAGE;
    }
    aenl_err_t err;
    aenl_err_clear(&err);
    char chan[256];
    aenl_curves_t c;
    if (compute_curves(&a, &c, chan, &err) != 0)
    {
        return AENL_EXIT_USAGE;
    }
    aenl_status_t st = write_curves(&a, &c, chan, &err);
    if (st == AENL_OK && (a.expansion != NULL || a.plot_expansion != NULL))
    {
        st = write_expansion_outputs(&a, &c, chan, &err);
    }
    if (st == AENL_OK && out_is_file(a.out))
    {
        print_summary(&a, &c, chan);
    }
    aenl_curves_free(&c);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE; /* 2 on bad input, I/O errors included */
    }
    return AENL_EXIT_OK;
}
