/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_identify_test.c
 * @brief `aenl identify --method test`: the record alone, by the likelihood-based test of
 *        aenl_nltest (argv has been parsed by cmd_identify.c).
 */
#include <stdio.h>
#include <stdlib.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_nltest.h"

static const char *const k_cmd = "identify";

int aenl_identify_by_test(const char *path, const char *channel, int json, double level)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_table_t t;
    if (aenl_table_read(path, &t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    long only = -1;
    if (channel != NULL && (only = aenl_cli_pick_channel(k_cmd, &t, path, channel)) < 0)
    {
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    if (aenl_cli_check_record(k_cmd, &t, path, only) != 0)
    {
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    /* the channels: every column but time, or the one named */
    size_t cols[AENL_NLT_MAX_CH];
    const char *names[AENL_NLT_MAX_CH];
    size_t nz = 0;
    for (size_t c = 0; c < t.n_cols; ++c)
    {
        if (aenl_cli_is_time_column(t.names[c]) || (only >= 0 && (long)c != only))
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
        aenl_cli_error(k_cmd, "%s: no data column (only time)", path);
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    const size_t n = t.n_rows;
    const double *chan[AENL_NLT_MAX_CH];
    for (size_t j = 0; j < nz; ++j)
    {
        chan[j] = t.data + cols[j] * n;
    }
    aenl_nlt_opts_t opts;
    aenl_nlt_opts_default(&opts);
    opts.level = level;
    aenl_nlt_result_t res;
    const aenl_status_t st = aenl_nlt_run_columns(chan, n, nz, &opts, &res, &err);
    int rc = AENL_EXIT_OK;
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s: %s", path, err.msg[0] ? err.msg : aenl_status_str(st));
        rc = st == AENL_E_DIM ? AENL_EXIT_FAIL : AENL_EXIT_USAGE;
    }
    else if (json)
    {
        if (aenl_nlt_print_json(stdout, &res, names, path) != AENL_OK)
        {
            aenl_cli_error(k_cmd, "out of memory while writing the JSON");
            rc = AENL_EXIT_FAIL;
        }
    }
    else
    {
        aenl_nlt_print_table(stdout, &res, names, path);
    }
    aenl_table_free(&t);
    return rc;
}
