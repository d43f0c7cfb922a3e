/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_plot.c
 * @brief `aenl plot KIND IN.csv -o OUT.png`: figures from the CSV outputs of the other subcommands.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_plot.h"

static const char *const k_cmd = "plot";

static void help(void)
{
    printf(
        "usage: aenl plot KIND IN.csv -o OUT.png|OUT.svg|OUT.pdf [--title T] [--marks x1,...]\n\n"
        "KIND  moments     IN from `aenl moments`: mean and variance per lag (--marks draws\n"
        "                  vertical lines, e.g. at switching points)\n"
        "      timeseries  IN from `aenl simulate` or any record whose first column is time:\n"
        "                  every channel against time\n"
        "The figure's format follows OUT's extension (PNG without one).\n");
}

/* A moments CSV as `aenl moments` writes it: whole lags >= 1, x finite and increasing within each
 * lag, some finite mean, no value gnuplot would choke on. One message naming the row otherwise. */
static int moments_check(const char *in, const aenl_table_t *t, const double *lag, const double *x,
                         const double *mean)
{
    size_t n_finite = 0;
    for (size_t r = 0; r < t->n_rows; ++r)
    {
        if (!(lag[r] >= 1.0 && lag[r] <= 1e9) || (double)(long)lag[r] < lag[r])
        {
            aenl_cli_error(k_cmd, "%s: data row %zu: lag %g is not a whole number >= 1", in, r + 1u,
                           lag[r]);
            return -1;
        }
        if (!isfinite(x[r]) || fabs(x[r]) > AENL_CLI_MAX_ABS ||
            (r > 0 && !(lag[r] > lag[r - 1u] || lag[r] < lag[r - 1u]) && !(x[r] > x[r - 1u])))
        {
            aenl_cli_error(k_cmd,
                           "%s: data row %zu: x %g is not finite and increasing within lag %g", in,
                           r + 1u, x[r], lag[r]);
            return -1;
        }
        if (fabs(mean[r]) > AENL_CLI_MAX_ABS)
        {
            aenl_cli_error(k_cmd, "%s: data row %zu: mean %g is too large (the limit is +-%g)", in,
                           r + 1u, mean[r], AENL_CLI_MAX_ABS);
            return -1;
        }
        n_finite += isnan(mean[r]) ? 0u : 1u;
    }
    if (n_finite == 0)
    {
        aenl_cli_error(k_cmd, "%s: no finite mean in any row (nothing to plot)", in);
        return -1;
    }
    return 0;
}

/* The distinct lags of a moments CSV (column "lag"), space-separated, in order of appearance. */
static int moments_lags(const char *in, char *lags, size_t n)
{
    aenl_table_t t;
    aenl_err_t err;
    aenl_err_clear(&err);
    if (aenl_table_read(in, &t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return -1;
    }
    const long c = aenl_table_find(&t, "lag");
    const long cx = aenl_table_find(&t, "x");
    const long cm = aenl_table_find(&t, "mean");
    if (c < 0 || cx < 0 || cm < 0 || aenl_table_find(&t, "var") < 0 || t.n_rows == 0)
    {
        aenl_cli_error(k_cmd, "%s: not a moments CSV (needs rows and columns lag,x,mean,var)", in);
        aenl_table_free(&t);
        return -1;
    }
    const double *lag = aenl_table_col(&t, (size_t)c);
    if (moments_check(in, &t, lag, aenl_table_col(&t, (size_t)cx),
                      aenl_table_col(&t, (size_t)cm)) != 0)
    {
        aenl_table_free(&t);
        return -1;
    }
    lags[0] = '\0';
    double last = -1.0;
    for (size_t r = 0; r < t.n_rows; ++r)
    {
        if (lag[r] > last || lag[r] < last)
        {
            char one[32];
            (void)snprintf(one, sizeof(one), "%s%.0f", lags[0] ? " " : "", lag[r]);
            const size_t len = strlen(lags), len_one = strlen(one);
            if (len + len_one + 1 < n && strstr(lags, one) == NULL)
            {
                memcpy(lags + len, one, len_one + 1u);
            }
            last = lag[r];
        }
    }
    aenl_table_free(&t);
    return 0;
}

/* The command line of `aenl plot`. */
typedef struct
{
    const char *kind, *in, *out, *title, *marks;
} plot_args_t;

/* Reads the options into a; returns the exit code when the command ends here (--help, a usage
 * error), -1 otherwise. */
static int parse_args(int argc, char **argv, plot_args_t *a)
{
    memset(a, 0, sizeof(*a));
    for (int i = 1; i < argc; ++i)
    {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)
        {
            help();
            return AENL_EXIT_OK;
        }
        if (strcmp(arg, "-o") == 0 || strcmp(arg, "--output") == 0)
        {
            if ((a->out = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(arg, "--title") == 0)
        {
            if ((a->title = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(arg, "--marks") == 0)
        {
            if ((a->marks = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (a->kind == NULL && arg[0] != '-')
        {
            a->kind = arg;
        }
        else if (aenl_cli_positional(k_cmd, arg, &a->in, "input file") != 0)
        {
            return AENL_EXIT_USAGE;
        }
    }
    if (a->kind == NULL || a->in == NULL || a->out == NULL)
    {
        aenl_cli_error(k_cmd, "usage: aenl plot KIND IN.csv -o OUT.png (aenl plot --help)");
        return AENL_EXIT_USAGE;
    }
    return -1;
}

/* --marks x1,x2,... as the space-separated words gnuplot iterates over, into words[n]. */
static int mark_words_of(const char *marks, char *words, size_t n)
{
    if (strlen(marks) >= n)
    {
        aenl_cli_error(k_cmd, "--marks: list too long");
        return -1;
    }
    for (const char *p = marks; *p; ++p)
    {
        double v;
        char *end;
        v = aenl_strtod_decimal(p, &end);
        if (end == p || (*end != ',' && *end != '\0') || !isfinite(v))
        {
            aenl_cli_error(k_cmd, "--marks: '%s' is not a comma-separated list of numbers", marks);
            return -1;
        }
        p = end;
        if (*p == '\0')
        {
            break;
        }
    }
    size_t j = 0;
    for (const char *p = marks; *p; ++p)
    {
        words[j++] = (char)((*p == ',') ? ' ' : *p);
    }
    words[j] = '\0';
    return 0;
}

/* A record to plot against time. Validated before gnuplot sees it: a clear error beats
 * gnuplot's. */
static int timeseries_check(const char *in)
{
    aenl_table_t t;
    aenl_err_t e;
    aenl_err_clear(&e);
    if (aenl_table_read(in, &t, &e) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", e.msg);
        return -1;
    }
    const int ok = t.n_rows > 0 && t.n_cols >= 2;
    if (!ok)
    {
        aenl_table_free(&t);
        aenl_cli_error(k_cmd, "%s: a time series needs a time column, a channel and rows", in);
        return -1;
    }
    if (!aenl_cli_is_time_column(t.names[0]))
    {
        const int is_moments = aenl_table_find(&t, "lag") >= 0;
        aenl_cli_error(k_cmd,
                       "%s: the first column '%s' is not a time column (t, time, tau or "
                       "timestamp, with or without a unit)%s",
                       in, t.names[0],
                       is_moments ? "; this looks like an `aenl moments` output: plot it "
                                    "with `aenl plot moments`"
                                  : "");
        aenl_table_free(&t);
        return -1;
    }
    const int bad = aenl_cli_check_record(k_cmd, &t, in, -1);
    aenl_table_free(&t);
    return bad ? -1 : 0;
}

int aenl_cmd_plot(int argc, char **argv)
{
    plot_args_t a;
    const int done = parse_args(argc, argv, &a);
    if (done >= 0)
    {
        return done;
    }
    aenl_plot_var_t vars[6];
    size_t nv = 0;
    /* vars[] points into these until aenl_plot_run below: they must outlive the if block. */
    /* cppcheck-suppress variableScope */
    char lags[256];
    /* cppcheck-suppress variableScope */
    char mark_words[512] = "";
    vars[nv++] = (aenl_plot_var_t){"in", a.in};
    vars[nv++] = (aenl_plot_var_t){"title", a.title ? a.title : a.in};
    if (strcmp(a.kind, "moments") == 0)
    {
        if (moments_lags(a.in, lags, sizeof(lags)) != 0)
        {
            return AENL_EXIT_USAGE;
        }
        vars[nv++] = (aenl_plot_var_t){"lags", lags};
        if (a.marks != NULL)
        {
            if (mark_words_of(a.marks, mark_words, sizeof(mark_words)) != 0)
            {
                return AENL_EXIT_USAGE;
            }
            vars[nv++] = (aenl_plot_var_t){"marks", mark_words};
        }
    }
    else if (strcmp(a.kind, "timeseries") != 0)
    {
        aenl_cli_error(k_cmd, "unknown kind '%s' (moments or timeseries)", a.kind);
        return AENL_EXIT_USAGE;
    }
    else if (timeseries_check(a.in) != 0)
    {
        return AENL_EXIT_USAGE;
    }
    aenl_err_t err;
    aenl_err_clear(&err);
    const aenl_status_t st = aenl_plot_run(a.kind, vars, nv, a.out, &err);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    printf("%s\n", a.out);
    return AENL_EXIT_OK;
}
