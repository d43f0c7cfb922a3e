/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_moments.c
 * @brief `aenl moments`: conditional mean/variance curves of one channel (paper Figs. 5-9).
 */
#define _POSIX_C_SOURCE 200809L

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
        "                    [--plot-expansion exp.png]\n\n"
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
        "--plot-expansion F  figure of it: acceleration and velocity against position\n");
}

static int parse_grid(const char *s, aenl_curves_opts_t *o)
{
    char buf[256];
    const size_t len = strlen(s);
    if (len >= sizeof(buf))
    {
        aenl_cli_error(k_cmd, "--grid: value too long");
        return -1;
    }
    memcpy(buf, s, len + 1u);
    char *a = buf;
    char *b = strchr(a, ':');
    char *c = b ? strchr(b + 1, ':') : NULL;
    if (b == NULL || c == NULL)
    {
        aenl_cli_error(k_cmd, "--grid: '%s' is not MIN:MAX:N", s);
        return -1;
    }
    *b++ = '\0';
    *c++ = '\0';
    long n = 0;
    if (aenl_cli_parse_double(k_cmd, "--grid MIN", a, &o->x_min) != 0 ||
        aenl_cli_parse_double(k_cmd, "--grid MAX", b, &o->x_max) != 0 ||
        aenl_cli_parse_long(k_cmd, "--grid N", c, 3, AENL_MOMENTS_MAX_GRID, &n) != 0)
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

/* An empty temporary file /tmp/aenl_<stem>_XXXXXX for a figure's data; its name into buf[64]. */
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
        st = aenl_plot_run("expansion", vars, sizeof(vars) / sizeof(vars[0]), png, err);
        if (st != AENL_OK && path != NULL)
        {
            (void)remove(path);
        }
    }
    if (tmp[0] != '\0')
    {
        (void)remove(tmp);
    }
    return st;
}

int aenl_cmd_moments(int argc, char **argv)
{
    const char *data = NULL, *channel = NULL, *out = NULL, *plot = NULL;
    const char *expansion = NULL, *plot_expansion = NULL;
    int dir = AENL_DIR_ALL;
    aenl_curves_opts_t o;
    aenl_curves_opts_default(&o);
    aenl_err_t err;
    aenl_err_clear(&err);

    for (int i = 1; i < argc; ++i)
    {
        const char *a = argv[i];
        const char *v = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
        {
            help();
            return AENL_EXIT_OK;
        }
        if (strcmp(a, "--channel") == 0)
        {
            if ((channel = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--lags") == 0)
        {
            if ((v = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
            if (strcmp(v, "auto") == 0)
            {
                o.lags_auto = 1;
            }
            else if (aenl_curves_parse_lags(v, &o, &err) != AENL_OK)
            {
                aenl_cli_error(k_cmd, "%s", err.msg);
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--prefilter") == 0)
        {
            if ((v = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
            if (strcmp(v, "auto") == 0)
            {
                o.prefilter = -1.0;
            }
            else if (strcmp(v, "off") == 0)
            {
                o.prefilter = 0.0;
            }
            else if (aenl_cli_parse_double(k_cmd, "--prefilter", v, &o.prefilter) != 0)
            {
                return AENL_EXIT_USAGE;
            }
            else if (!(o.prefilter > 0.0 && o.prefilter < 0.5))
            {
                aenl_cli_error(k_cmd, "--prefilter: %s is not auto, off or a cutoff in (0, 0.5)",
                               v);
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--expansion") == 0)
        {
            if ((expansion = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--plot-expansion") == 0)
        {
            if ((plot_expansion = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--grid") == 0)
        {
            if ((v = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL || parse_grid(v, &o) != 0)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--bandwidth") == 0)
        {
            if ((v = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
            if (strcmp(v, "cv") == 0)
            {
                o.bandwidth = 0.0;
            }
            else if (aenl_cli_parse_double(k_cmd, "--bandwidth", v, &o.bandwidth) != 0)
            {
                return AENL_EXIT_USAGE;
            }
            else if (!(o.bandwidth > 0.0))
            {
                aenl_cli_error(k_cmd, "--bandwidth: %s must be positive (or 'cv')", v);
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--direction") == 0)
        {
            if ((v = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
            if (strcmp(v, "all") == 0)
            {
                dir = AENL_DIR_ALL;
            }
            else if (strcmp(v, "rising") == 0)
            {
                dir = AENL_DIR_RISING;
            }
            else if (strcmp(v, "falling") == 0)
            {
                dir = AENL_DIR_FALLING;
            }
            else
            {
                aenl_cli_error(k_cmd, "--direction: '%s' is not all, rising or falling", v);
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--no-split") == 0)
        {
            o.split = 0;
        }
        else if (strcmp(a, "--forgetting") == 0)
        {
            if ((v = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL ||
                aenl_cli_parse_double(k_cmd, "--forgetting", v, &o.forgetting) != 0)
            {
                return AENL_EXIT_USAGE;
            }
            if (!(o.forgetting >= AENL_MOMENTS_MIN_FORGETTING) || o.forgetting > 1.0)
            {
                aenl_cli_error(k_cmd, "--forgetting: %s is outside [%g, 1]", v,
                               AENL_MOMENTS_MIN_FORGETTING);
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0)
        {
            if ((out = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--plot") == 0)
        {
            if ((plot = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (aenl_cli_positional(k_cmd, a, &data, "data file") != 0)
        {
            return AENL_EXIT_USAGE;
        }
    }
    if (data == NULL)
    {
        aenl_cli_error(k_cmd, "no data file (usage: aenl moments DATA.csv --channel C ...)");
        return AENL_EXIT_USAGE;
    }
    if (dir != AENL_DIR_ALL && !o.split)
    {
        aenl_cli_error(k_cmd, "--direction %s needs the direction split (drop --no-split)",
                       dir == AENL_DIR_RISING ? "rising" : "falling");
        return AENL_EXIT_USAGE;
    }
    if ((expansion != NULL || plot_expansion != NULL) && !o.lags_auto && o.n_lags < 3u)
    {
        aenl_cli_error(k_cmd, "--expansion needs at least 3 lags (--lags auto or a list)");
        return AENL_EXIT_USAGE;
    }
    if ((plot != NULL || plot_expansion != NULL) && !aenl_plot_available())
    {
        aenl_cli_error(k_cmd, "--plot needs gnuplot on PATH (Debian: apt-get install gnuplot-nox)");
        return AENL_EXIT_USAGE;
    }

    aenl_table_t t;
    if (aenl_table_read(data, &t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    const long col = aenl_cli_pick_channel(k_cmd, &t, data, channel);
    if (col < 0 || aenl_cli_check_record(k_cmd, &t, data, col) != 0)
    {
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    char chan[256];
    (void)snprintf(chan, sizeof(chan), "%s", t.names[col]); /* a label: truncation is fine */
    if (t.n_rows == 0)
    {
        aenl_cli_error(k_cmd, "%s: no data rows (header only)", data);
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    aenl_curves_t c;
    aenl_status_t st = aenl_curves_compute(aenl_table_col(&t, (size_t)col), t.n_rows, &o, &c, &err);
    aenl_table_free(&t);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s, channel %s: %s", data, chan, err.msg);
        return AENL_EXIT_USAGE;
    }

    /* The plot needs the CSV on disk: the output file, or a temporary one. */
    char tmp_csv[64] = "";
    const char *csv_path = out;
    if (plot != NULL && (out == NULL || strcmp(out, "-") == 0))
    {
        st = make_tmp(tmp_csv, "moments", &err);
        if (st == AENL_OK)
        {
            st = aenl_curves_write_csv(&c, dir, data, chan, tmp_csv, &err);
            csv_path = tmp_csv;
        }
    }
    if (st == AENL_OK && (out == NULL || strcmp(out, "-") == 0) && plot == NULL)
    {
        st = aenl_curves_write_csv(&c, dir, data, chan, NULL, &err);
    }
    else if (st == AENL_OK && out != NULL && strcmp(out, "-") != 0)
    {
        st = aenl_curves_write_csv(&c, dir, data, chan, out, &err);
    }
    if (st == AENL_OK && plot != NULL)
    {
        /* 64 lags of up to 4 digits need 320 bytes: bounded append (was strcat into 256 B). */
        char lags[AENL_MOMENTS_MAX_LAGS * 6 + 1] = "";
        size_t lags_len = 0;
        for (uint16_t i = 0; i < c.n_lags && lags_len < sizeof(lags); ++i)
        {
            const int w = snprintf(lags + lags_len, sizeof(lags) - lags_len, "%s%u", i ? " " : "",
                                   (unsigned)c.lags[i]);
            lags_len += (w > 0) ? (size_t)w : 0u;
        }
        char title[600];
        const char *base = strrchr(data, '/') ? strrchr(data, '/') + 1 : data;
        (void)snprintf(title, sizeof(title), "%s: %s (h = %.3g, %s)", base, chan, c.bandwidth,
                       dir == AENL_DIR_ALL      ? "all pairs"
                       : dir == AENL_DIR_RISING ? "rising"
                                                : "falling");
        for (char *p = title; *p; ++p)
        {
            *p = (char)((*p == '\'' || *p == '\n') ? ' ' : *p);
        }
        const aenl_plot_var_t vars[] = {
            {"in", csv_path}, {"lags", lags}, {"title", title}, {"xlabel", chan}};
        st = aenl_plot_run("moments", vars, sizeof(vars) / sizeof(vars[0]), plot, &err);
        if (st != AENL_OK && out != NULL && strcmp(out, "-") != 0)
        {
            (void)remove(out); /* all or nothing: no CSV without its requested figure */
        }
    }
    if (tmp_csv[0] != '\0')
    {
        (void)remove(tmp_csv);
    }
    if (st == AENL_OK && (expansion != NULL || plot_expansion != NULL))
    {
        st = write_expansion(&c, data, chan, expansion, plot_expansion, &err);
        if (st != AENL_OK && out != NULL && strcmp(out, "-") != 0 && plot == NULL)
        {
            (void)remove(out); /* all or nothing */
        }
        if (st != AENL_OK && plot != NULL)
        {
            (void)remove(plot);
            if (out != NULL && strcmp(out, "-") != 0)
            {
                (void)remove(out);
            }
        }
    }
    if (st == AENL_OK && out != NULL && strcmp(out, "-") != 0)
    {
        printf("%s: channel %s, %zu samples (%zu missing), lags", data, chan, c.n_samples,
               c.n_missing);
        for (uint16_t i = 0; i < c.n_lags; ++i)
        {
            printf("%s%u", i ? "," : " ", (unsigned)c.lags[i]);
        }
        printf(", grid [%.6g, %.6g] x %u, bandwidth %.6g (%s) -> %s%s%s\n", c.x[0],
               c.x[c.n_grid - 1u], (unsigned)c.n_grid, c.bandwidth,
               c.bw_method < 0 ? "given" : aenl_bw_method_str(c.bw_method), out, plot ? ", " : "",
               plot ? plot : "");
    }
    if (st == AENL_OK && (c.period > 0.0 || c.prefilter > 0.0) && out != NULL &&
        strcmp(out, "-") != 0)
    {
        printf("  period %.4g samples, pre-filter cutoff %.4g of the sample rate\n", c.period,
               c.prefilter);
    }
    aenl_curves_free(&c);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE; /* 2 on bad input, I/O errors included */
    }
    return AENL_EXIT_OK;
}
