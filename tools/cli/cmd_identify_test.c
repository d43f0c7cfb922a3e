/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_identify_test.c
 * @brief `aenl identify --method test`: the record alone, by the likelihood-based test of
 *        aenl_nltest (argv has been parsed by cmd_identify.c).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_em.h"
#include "aenl_tools/aenl_nltest.h"

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

static int is_input(const size_t *in, long n_in, size_t c)
{
    for (long k = 0; k < n_in; ++k)
    {
        if (in[k] == c)
        {
            return 1;
        }
    }
    return 0;
}

int aenl_identify_by_test(const char *path, const char *channel, const char *inputs, int json,
                          double level, size_t n_controls)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_table_t t;
    if (aenl_table_read(path, &t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    size_t in[AENL_NLT_MAX_INPUT];
    const long n_in = inputs != NULL ? input_columns(&t, path, inputs, in) : 0;
    long only = -1;
    if (n_in < 0 ||
        (channel != NULL && (only = aenl_cli_pick_channel(k_cmd, &t, path, channel)) < 0))
    {
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    if (only >= 0 && is_input(in, n_in, (size_t)only))
    {
        aenl_cli_error(k_cmd, "--channel %s is also an --input", channel);
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    if (t.n_rows == 0)
    {
        aenl_cli_error(k_cmd, "%s: no data rows (header only)", path);
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    if (aenl_cli_check_record(k_cmd, &t, path, only) != 0)
    {
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    /* the channels: every column but time and the inputs, or the one named */
    size_t cols[AENL_NLT_MAX_CH];
    const char *names[AENL_NLT_MAX_CH];
    size_t nz = 0;
    for (size_t c = 0; c < t.n_cols; ++c)
    {
        if (aenl_cli_is_time_column(t.names[c]) || is_input(in, n_in, c) ||
            (only >= 0 && (long)c != only))
        {
            continue;
        }
        if (nz == AENL_NLT_MAX_CH)
        {
            aenl_cli_error(k_cmd, "%s: more than %d channels: name one with --channel", path,
                           AENL_NLT_MAX_CH);
            aenl_table_free(&t);
            return AENL_EXIT_USAGE;
        }
        cols[nz] = c;
        names[nz++] = t.names[c];
    }
    if (nz == 0)
    {
        aenl_cli_error(k_cmd,
                       n_in > 0 ? "%s: no channel left to test (only time and inputs)"
                                : "%s: no data column (only the time column)",
                       path);
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    const size_t n = t.n_rows;
    const double *chan[AENL_NLT_MAX_CH];
    for (size_t j = 0; j < nz; ++j)
    {
        chan[j] = t.data + cols[j] * n;
        double lo = HUGE_VAL;
        double hi = -HUGE_VAL;
        for (size_t k = 0; k < n; ++k)
        {
            lo = fmin(lo, chan[j][k]); /* fmin and fmax pass over a missing sample */
            hi = fmax(hi, chan[j][k]);
        }
        if (!(hi > lo)) /* nothing to test, whatever the record's length */
        {
            aenl_cli_error(k_cmd,
                           "%s, channel %s: constant signal (every sample is %g): nothing to "
                           "identify (name another channel with --channel)",
                           path, names[j], lo);
            aenl_table_free(&t);
            return AENL_EXIT_USAGE;
        }
    }
    const double *in_cols[AENL_NLT_MAX_INPUT];
    const char *in_names[AENL_NLT_MAX_INPUT];
    for (long k = 0; k < n_in; ++k)
    {
        in_cols[k] = t.data + in[k] * n;
        in_names[k] = t.names[in[k]];
    }
    aenl_nlt_opts_t opts;
    aenl_nlt_opts_default(&opts);
    opts.level = level;
    opts.input = n_in > 0 ? in_cols : NULL;
    opts.n_input = (size_t)n_in;
    opts.n_controls = n_controls;
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
    else if (json)
    {
        if (aenl_nlt_print_json(stdout, &res, names, in_names, path) != AENL_OK)
        {
            aenl_cli_error(k_cmd, "out of memory while writing the JSON");
            rc = AENL_EXIT_FAIL;
        }
    }
    else
    {
        aenl_nlt_print_table(stdout, &res, names, in_names, path);
    }
    aenl_table_free(&t);
    return rc;
}
