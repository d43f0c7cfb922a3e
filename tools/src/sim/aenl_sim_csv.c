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
    const size_t n = res->n_samples, nc = res->n_channels;
    if (path == NULL || strcmp(path, "-") == 0)
    {
        printf("t");
        for (size_t c = 0; c < nc; ++c)
        {
            printf(",%s", res->names[c + 1u]);
        }
        printf("\n");
        for (size_t k = 0; k < n; ++k)
        {
            printf("%.17g", res->t[k]);
            for (size_t c = 0; c < nc; ++c)
            {
                printf(",%.17g", res->y[c * n + k]);
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
    aenl_status_t st = aenl_csv_writer_open(&w, path, res->names, nc + 1u, err);
    double row[4];
    for (size_t k = 0; k < n && st == AENL_OK; ++k)
    {
        row[0] = res->t[k];
        for (size_t c = 0; c < nc && c < 3u; ++c)
        {
            row[c + 1u] = res->y[c * n + k];
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
