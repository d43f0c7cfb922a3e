/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sim_csv.c
 * @brief Simulation results as CSV (shared by `aenl simulate`, the demo and the checks).
 */
#include <stdio.h>
#include <string.h>

#include "aenl_tools/aenl_csv.h"
#include "aenl_tools/aenl_sim.h"

aenl_status_t aenl_sim_result_write_csv(const aenl_sim_result_t *res, const char *path,
                                        aenl_err_t *err)
{
    const size_t n = res->n_samples;
    const size_t nc = res->n_channels;
    /* t, the channels, then the forced excitation when there is one */
    const char *names[5];
    const double *col[5];
    size_t ncol = 0;
    names[ncol] = res->names[0];
    col[ncol++] = res->t;
    for (size_t c = 0; c < nc && c < 3u; ++c)
    {
        names[ncol] = res->names[c + 1u];
        col[ncol++] = res->y + c * n;
    }
    if (res->u != NULL)
    {
        names[ncol] = res->u_name != NULL ? res->u_name : "f";
        col[ncol++] = res->u;
    }
    if (path == NULL || strcmp(path, "-") == 0)
    {
        for (size_t c = 0; c < ncol; ++c)
        {
            printf(c == 0 ? "%s" : ",%s", names[c]);
        }
        printf("\n");
        for (size_t k = 0; k < n; ++k)
        {
            for (size_t c = 0; c < ncol; ++c)
            {
                printf(c == 0 ? "%.17g" : ",%.17g", col[c][k]);
            }
            printf("\n");
        }
        if (fflush(stdout) != 0 || ferror(stdout))
        {
            aenl_err_set(err, "writing to standard output failed");
            return AENL_E_IO;
        }
        return AENL_OK;
    }
    aenl_csv_writer_t w;
    memset(&w, 0, sizeof(w));
    aenl_status_t st = aenl_csv_writer_open(&w, path, names, ncol, err);
    double row[5];
    for (size_t k = 0; k < n && st == AENL_OK; ++k)
    {
        for (size_t c = 0; c < ncol; ++c)
        {
            row[c] = col[c][k];
        }
        st = aenl_csv_writer_row(&w, row, err);
    }
    if (st == AENL_OK)
    {
        return aenl_csv_writer_commit(&w, err);
    }
    aenl_csv_writer_abort(&w);
    return st;
}
