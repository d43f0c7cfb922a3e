/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_csv.c
 * @brief libFuzzer target: the host CSV reader (aenl_table_read, hence aenl_csv_open/next) on
 *        arbitrary bytes, then a write/read round trip of whatever it accepted.
 *
 * The reader takes a path, so each input is written to a per-process temporary file first.
 * Properties checked (abort() on violation):
 *  - the status is one of OK, E_IO, E_EMPTY, E_ARG, E_NUMERIC; on error the message is set, is one
 *    line, names the file, and the table is left zeroed (no leak: LeakSanitizer);
 *  - on success: at least one column, names non-empty and distinct, every value finite or NaN,
 *    n_nan counts the NaN cells;
 *  - an accepted table whose names the writer takes (it refuses names the reader would mangle)
 *    writes and reads back bit for bit (%.17g round trip, NaN as "nan").
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define FUZZ_NAME "fuzz_csv"
#include "fuzz_common.h"

#include "aenl_tools/aenl_csv.h"

static char g_in_path[256];
static char g_out_path[256];

static void make_paths(void)
{
    if (g_in_path[0] == '\0')
    {
        const char *dir = getenv("TMPDIR");
        if (dir == NULL || dir[0] == '\0')
        {
            dir = "/tmp";
        }
        snprintf(g_in_path, sizeof(g_in_path), "%s/aenl_fuzz_csv_in.%ld.csv", dir, (long)getpid());
        snprintf(g_out_path, sizeof(g_out_path), "%s/aenl_fuzz_csv_out.%ld.csv", dir,
                 (long)getpid());
    }
}

static int table_is_zero(const aenl_table_t *t)
{
    return t->n_rows == 0u && t->n_cols == 0u && t->names == NULL && t->data == NULL &&
           t->n_nan == NULL;
}

static void check_error(aenl_status_t st, const aenl_err_t *err, const aenl_table_t *t,
                        const char *path)
{
    CHECK(st == AENL_E_IO || st == AENL_E_EMPTY || st == AENL_E_ARG || st == AENL_E_NUMERIC,
          "unexpected status");
    CHECK(err->msg[0] != '\0', "error without a message");
    CHECK(strchr(err->msg, '\n') == NULL, "message spans lines");
    CHECK(strstr(err->msg, path) != NULL, "message does not name the file");
    CHECK(table_is_zero(t), "failed read left the table non-empty");
}

static void check_table(const aenl_table_t *t)
{
    CHECK(t->n_cols >= 1u && t->names != NULL && t->n_nan != NULL, "accepted an empty header");
    CHECK(t->n_rows == 0u || t->data != NULL, "rows without data");
    for (size_t c = 0; c < t->n_cols; ++c)
    {
        CHECK(t->names[c] != NULL && t->names[c][0] != '\0', "empty column name");
        CHECK(strchr(t->names[c], ',') == NULL, "column name holds a comma");
        for (size_t k = 0; k < c; ++k)
        {
            CHECK(strcmp(t->names[k], t->names[c]) != 0, "duplicate column name accepted");
        }
        CHECK(aenl_table_find(t, t->names[c]) == (long)c, "find does not return the column");
        size_t n_nan = 0;
        const double *col = aenl_table_col(t, c);
        for (size_t r = 0; r < t->n_rows; ++r)
        {
            CHECK(!isinf(col[r]), "infinite value accepted");
            n_nan += isnan(col[r]) ? 1u : 0u;
        }
        CHECK(n_nan == t->n_nan[c], "n_nan disagrees with the data");
    }
}

static void round_trip(const aenl_table_t *t)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_status_t st = aenl_table_write(t, g_out_path, &err);
    if (st != AENL_OK)
    {
        /* Only a name the writer refuses (quote, leading '#', ...) may stop it here. */
        CHECK(st == AENL_E_ARG && strstr(err.msg, "column name") != NULL, "write failed");
        CHECK(access(g_out_path, F_OK) != 0, "failed write left a file");
        return;
    }
    aenl_table_t back;
    aenl_err_clear(&err);
    st = aenl_table_read(g_out_path, &back, &err);
    CHECK(st == AENL_OK, "written table does not read back");
    CHECK(back.n_rows == t->n_rows && back.n_cols == t->n_cols, "round trip changed the shape");
    for (size_t c = 0; c < t->n_cols; ++c)
    {
        CHECK(strcmp(back.names[c], t->names[c]) == 0, "round trip changed a name");
        const double *a = aenl_table_col(t, c);
        const double *b = aenl_table_col(&back, c);
        for (size_t r = 0; r < t->n_rows; ++r)
        {
            CHECK((isnan(a[r]) && isnan(b[r])) || memcmp(&a[r], &b[r], sizeof(double)) == 0,
                  "round trip changed a value");
        }
    }
    aenl_table_free(&back);
    (void)unlink(g_out_path);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    make_paths();
    FILE *f = fopen(g_in_path, "wb");
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

    aenl_table_t t;
    aenl_err_t err;
    aenl_err_clear(&err);
    memset(&t, 0x5A, sizeof(t));
    const aenl_status_t st = aenl_table_read(g_in_path, &t, &err);
    if (st != AENL_OK)
    {
        check_error(st, &err, &t, g_in_path);
    }
    else
    {
        CHECK(err.msg[0] == '\0', "success with an error message");
        check_table(&t);
        round_trip(&t);
        aenl_table_free(&t);
        CHECK(table_is_zero(&t), "free did not zero the table");
    }
    (void)unlink(g_in_path);
    return 0;
}
