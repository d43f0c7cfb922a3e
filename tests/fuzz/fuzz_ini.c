/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_ini.c
 * @brief libFuzzer target: the model INI loader (aenl_sim_load_ini) on arbitrary bytes, with and
 *        without a [run] (simulation vs flutter analysis). Nothing is simulated.
 *
 * The loader takes a path, so each input is written to a per-process temporary file first.
 * Properties checked (abort() on violation):
 *  - the status is OK, E_ARG or E_DIM (E_IO only if the temporary vanished); on error the message
 *    is set, is one line and names the file;
 *  - an accepted model (and run) passes aenl_sim_validate();
 *  - a file accepted with a run is accepted as a model alone too (the run is only optional more).
 */
#define _POSIX_C_SOURCE 200809L

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define FUZZ_NAME "fuzz_ini"
#include "fuzz_common.h"

#include "aenl_tools/aenl_sim.h"

static char g_path[256];

static void check_status(aenl_status_t st, const aenl_err_t *err)
{
    if (st == AENL_OK)
    {
        CHECK(err->msg[0] == '\0', "success with an error message");
        return;
    }
    CHECK(st == AENL_E_ARG || st == AENL_E_DIM, "unexpected status");
    CHECK(err->msg[0] != '\0', "error without a message");
    CHECK(strchr(err->msg, '\n') == NULL, "message spans lines");
    CHECK(strstr(err->msg, g_path) != NULL, "message does not name the file");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (g_path[0] == '\0')
    {
        const char *dir = getenv("TMPDIR");
        snprintf(g_path, sizeof(g_path), "%s/aenl_fuzz_ini.%ld.ini",
                 (dir != NULL && dir[0] != '\0') ? dir : "/tmp", (long)getpid());
    }
    FILE *f = fopen(g_path, "wb");
    if (f == NULL)
    {
        return 0;
    }
    if (size > 0u && fwrite(data, 1, size, f) != size)
    {
        fclose(f);
        return 0;
    }
    fclose(f);

    aenl_sim_model_t model;
    aenl_sim_run_t run;
    aenl_err_t err;
    aenl_err_clear(&err);
    const aenl_status_t st_run = aenl_sim_load_ini(g_path, &model, &run, &err);
    check_status(st_run, &err);
    if (st_run == AENL_OK)
    {
        aenl_err_clear(&err);
        CHECK(aenl_sim_validate(&model, &run, &err) == AENL_OK, "loaded model/run do not validate");
    }

    aenl_err_clear(&err);
    const aenl_status_t st_model = aenl_sim_load_ini(g_path, &model, NULL, &err);
    check_status(st_model, &err);
    if (st_model == AENL_OK)
    {
        aenl_err_clear(&err);
        CHECK(aenl_sim_validate(&model, NULL, &err) == AENL_OK, "loaded model does not validate");
    }
    CHECK(st_run != AENL_OK || st_model == AENL_OK, "accepted with a run but not as a model alone");
    (void)unlink(g_path);
    return 0;
}
