/* SPDX-License-Identifier: MIT */
/**
 * @file test_csv.c
 * @brief Host tools: CSV reader/writer and atomic output files (aenl_csv.h, aenl_io.h).
 */
#define _DEFAULT_SOURCE /* mknod, makedev */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <fcntl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "unity.h"

#include "aenl_test_device.h"
#include "aenl_test_rand.h"

#include "aenl_tools/aenl_csv.h"
#include "aenl_tools/aenl_io.h"
#include "aenl_tools/aenl_plot.h"

#ifndef AENL_TEST_TMP_DIR
#define AENL_TEST_TMP_DIR "."
#endif

static aenl_err_t g_err;
static char g_path[1024];

void setUp(void)
{
    aenl_err_clear(&g_err);
}

void tearDown(void)
{
}

/* ---- helpers ------------------------------------------------------------------------------- */

static const char *tmp_path(const char *name)
{
    (void)snprintf(g_path, sizeof g_path, "%s/%s", AENL_TEST_TMP_DIR, name);
    return g_path;
}

static void write_bytes(const char *path, const char *bytes, size_t n)
{
    FILE *fp = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL_MESSAGE(fp, path);
    TEST_ASSERT_EQUAL_size_t(n, fwrite(bytes, 1, n, fp));
    TEST_ASSERT_EQUAL_INT(0, fclose(fp));
}

static void write_text(const char *path, const char *text)
{
    write_bytes(path, text, strlen(text));
}

static int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Number of entries in the test folder whose name contains `part` (temporaries: ".tmp."). */
static int count_entries_with(const char *part)
{
    int n = 0;
    struct dirent *e;
    DIR *d = opendir(AENL_TEST_TMP_DIR);
    TEST_ASSERT_NOT_NULL(d);
    while ((e = readdir(d)) != NULL)
    {
        if (strstr(e->d_name, part) != NULL)
        {
            ++n;
        }
    }
    (void)closedir(d);
    return n;
}

static uint64_t g_lcg = 88172645463325252ULL;

static double bits_to_double(uint64_t b)
{
    double d;
    memcpy(&d, &b, sizeof d);
    return d;
}

/* Read `text` as a table expecting failure; check status and that the message holds `want`. */
static void expect_read_error(const char *name, const char *text, size_t len,
                              aenl_status_t want_status, const char *want)
{
    aenl_table_t t;
    aenl_status_t st;
    const char *path = tmp_path(name);
    write_bytes(path, text, len);
    aenl_err_clear(&g_err);
    st = aenl_table_read(path, &t, &g_err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(want_status, st, g_err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, want), g_err.msg);
    TEST_ASSERT_NULL(t.data);
    TEST_ASSERT_NULL(t.names);
    TEST_ASSERT_EQUAL_size_t(0, t.n_rows);
    (void)remove(path);
}

/* ---- errors -------------------------------------------------------------------------------- */

static void test_err_keeps_first_cause(void)
{
    aenl_err_set(&g_err, "first %d", 1);
    aenl_err_set(&g_err, "second %d", 2);
    TEST_ASSERT_EQUAL_STRING("first 1", g_err.msg);
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_STRING("", g_err.msg);
    aenl_err_set(NULL, "ignored"); /* NULL err is allowed */
}

/* ---- round trips --------------------------------------------------------------------------- */

static void test_table_round_trip_is_bit_exact(void)
{
    const char *names[] = {"t_s", "alpha", "beta"};
    const size_t n_rows = 4000;
    aenl_table_t t;
    aenl_table_t r;
    size_t i;
    size_t c;
    const char *path = tmp_path("round_trip.csv");
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_table_alloc(&t, n_rows, 3, names, &g_err));
    for (i = 0; i < n_rows; ++i)
    {
        uint64_t bits = ((uint64_t)(test_uniform0(&g_lcg) * 4294967296.0) << 32) |
                        (uint64_t)(test_uniform0(&g_lcg) * 4294967296.0);
        double v = bits_to_double(bits);
        aenl_table_col(&t, 0)[i] = (double)i * 0.1;
        aenl_table_col(&t, 1)[i] = isfinite(v) ? v : 1.0 / 3.0; /* random bit patterns */
        aenl_table_col(&t, 2)[i] = (test_uniform0(&g_lcg) - 0.5) * 1e-3;
    }
    /* Corner values. */
    aenl_table_col(&t, 1)[0] = -0.0;
    aenl_table_col(&t, 1)[1] = 4.9406564584124654e-324; /* smallest subnormal */
    aenl_table_col(&t, 1)[2] = 1.7976931348623157e308;
    aenl_table_col(&t, 1)[3] = -2.2250738585072014e-308;
    aenl_table_col(&t, 2)[5] = (double)NAN;
    aenl_table_col(&t, 2)[7] = (double)NAN;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_write(&t, path, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &r, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_size_t(n_rows, r.n_rows);
    TEST_ASSERT_EQUAL_size_t(3, r.n_cols);
    for (c = 0; c < 3; ++c)
    {
        TEST_ASSERT_EQUAL_STRING(names[c], r.names[c]);
        for (i = 0; i < n_rows; ++i)
        {
            double a = aenl_table_col(&t, c)[i];
            double b = aenl_table_col(&r, c)[i];
            if (isnan(a))
            {
                TEST_ASSERT_TRUE(isnan(b));
            }
            else
            {
                TEST_ASSERT_EQUAL_MEMORY(&a, &b, sizeof a);
            }
        }
    }
    TEST_ASSERT_EQUAL_size_t(0, r.n_nan[0]);
    TEST_ASSERT_EQUAL_size_t(0, r.n_nan[1]);
    TEST_ASSERT_EQUAL_size_t(2, r.n_nan[2]);
    TEST_ASSERT_EQUAL_INT(1, (int)aenl_table_find(&r, "alpha"));
    TEST_ASSERT_EQUAL_INT(-1, (int)aenl_table_find(&r, "gamma"));
    aenl_table_free(&t);
    aenl_table_free(&r);
    aenl_table_free(&r); /* safe twice */
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    (void)remove(path);
}

static void test_csv_writer_streams_rows(void)
{
    const char *names[] = {"t", "x"};
    aenl_csv_writer_t w;
    aenl_csv_t *csv = NULL;
    double row[2];
    int i;
    int rc;
    const char *path = tmp_path("writer.csv");
    (void)remove(path);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_csv_writer_open(&w, path, names, 2, &g_err));
    for (i = 0; i < 10; ++i)
    {
        row[0] = i;
        row[1] = (i == 3) ? (double)NAN : 0.5 * i;
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_csv_writer_row(&w, row, &g_err));
    }
    TEST_ASSERT_FALSE(file_exists(path));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_csv_writer_commit(&w, &g_err));
    TEST_ASSERT_TRUE(file_exists(path));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_csv_open(&csv, path, &g_err));
    TEST_ASSERT_EQUAL_size_t(2, aenl_csv_n_cols(csv));
    TEST_ASSERT_EQUAL_STRING("x", aenl_csv_col_name(csv, 1));
    TEST_ASSERT_NULL(aenl_csv_col_name(csv, 2));
    TEST_ASSERT_EQUAL_INT(1, (int)aenl_csv_find(csv, "x"));
    TEST_ASSERT_EQUAL_INT(-1, (int)aenl_csv_find(csv, "y"));
    TEST_ASSERT_EQUAL_STRING(path, aenl_csv_path(csv));
    for (i = 0; (rc = aenl_csv_next(csv, row, &g_err)) == 1; ++i)
    {
        TEST_ASSERT_EQUAL_DOUBLE((double)i, row[0]);
        if (i == 3)
        {
            TEST_ASSERT_TRUE(isnan(row[1]));
        }
        else
        {
            TEST_ASSERT_EQUAL_DOUBLE(0.5 * i, row[1]);
        }
        TEST_ASSERT_EQUAL_UINT32((uint32_t)(i + 2), (uint32_t)aenl_csv_line(csv));
    }
    TEST_ASSERT_EQUAL_INT(0, rc);
    TEST_ASSERT_EQUAL_INT(10, i);
    aenl_csv_close(csv);
    (void)remove(path);
}

static void test_csv_writer_rejects_bad_names_and_inf(void)
{
    const char *bad[] = {"t", "a,b"};
    const char *dup[] = {"t", "t"};
    const char *ok[] = {"t", "x"};
    aenl_csv_writer_t w;
    double row[2] = {1.0, (double)INFINITY};
    const char *path = tmp_path("writer_bad.csv");
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_csv_writer_open(&w, path, bad, 2, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "invalid column name 'a,b'"), g_err.msg);
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_csv_writer_open(&w, path, dup, 2, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "duplicate column name 't'"), g_err.msg);
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_csv_writer_open(&w, path, ok, 2, &g_err));
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_csv_writer_row(&w, row, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "column 2: infinite value"), g_err.msg);
    /* The failed row dropped the file: commit fails, abort is safe, nothing is left. */
    TEST_ASSERT_NOT_EQUAL(AENL_OK, aenl_csv_writer_commit(&w, NULL));
    aenl_csv_writer_abort(&w);
    TEST_ASSERT_FALSE(file_exists(path));
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
}

/* ---- reading details ----------------------------------------------------------------------- */

static void test_csv_reads_crlf(void)
{
    aenl_table_t t;
    const char *path = tmp_path("crlf.csv");
    write_text(path, "t,x\r\n0,1.5\r\n1,-2e-3\r\n2,\r\n");
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &t, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_size_t(3, t.n_rows);
    TEST_ASSERT_EQUAL_STRING("x", t.names[1]);
    TEST_ASSERT_EQUAL_DOUBLE(1.5, aenl_table_col(&t, 1)[0]);
    TEST_ASSERT_EQUAL_DOUBLE(-2e-3, aenl_table_col(&t, 1)[1]);
    TEST_ASSERT_TRUE(isnan(aenl_table_col(&t, 1)[2]));
    TEST_ASSERT_EQUAL_size_t(1, t.n_nan[1]);
    aenl_table_free(&t);
    (void)remove(path);
}

/* A header without a comma names the separator: semicolons or tabs (a spreadsheet's export);
 * the values are the same as with commas, and a decimal comma is named in the error. */
static void test_csv_reads_semicolons_and_tabs(void)
{
    static const char *const k_text[] = {"t;x;y\n0;1.5;-2\n0.5;;3e-3\n",
                                         "t\tx\ty\n0\t1.5\t-2\n0.5\t\t3e-3\n",
                                         " t ; x ;y\r\n0 ; 1.5;-2\r\n0.5; ;3e-3\r\n"};
    for (size_t k = 0; k < sizeof(k_text) / sizeof(k_text[0]); ++k)
    {
        aenl_table_t t;
        const char *path = tmp_path("sep.csv");
        write_text(path, k_text[k]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &t, &g_err), g_err.msg);
        TEST_ASSERT_EQUAL_size_t(3, t.n_cols);
        TEST_ASSERT_EQUAL_size_t(2, t.n_rows);
        TEST_ASSERT_EQUAL_STRING("x", t.names[1]);
        TEST_ASSERT_EQUAL_STRING("y", t.names[2]);
        TEST_ASSERT_EQUAL_DOUBLE(0.5, aenl_table_col(&t, 0)[1]);
        TEST_ASSERT_EQUAL_DOUBLE(1.5, aenl_table_col(&t, 1)[0]);
        TEST_ASSERT_TRUE(isnan(aenl_table_col(&t, 1)[1]));
        TEST_ASSERT_EQUAL_DOUBLE(3e-3, aenl_table_col(&t, 2)[1]);
        aenl_table_free(&t);
        (void)remove(path);
    }
    aenl_table_t t;
    const char *path = tmp_path("decimal_comma.csv");
    write_text(path, "t;x\n0;1,5\n");
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_table_read(path, &t, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(g_err.msg, ":2:2 (x): not a number '1,5' (a decimal comma?"), g_err.msg);
    (void)remove(path);
}

static void test_csv_strips_bom_and_trims_names(void)
{
    aenl_table_t t;
    const char *path = tmp_path("bom.csv");
    write_text(path, "\xEF\xBB\xBF t_s ,  alpha\t, \"beta\"\n 1 , 2 ,3\n");
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &t, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_STRING("t_s", t.names[0]);
    TEST_ASSERT_EQUAL_STRING("alpha", t.names[1]);
    TEST_ASSERT_EQUAL_STRING("beta", t.names[2]);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, aenl_table_col(&t, 0)[0]);
    TEST_ASSERT_EQUAL_DOUBLE(2.0, aenl_table_col(&t, 1)[0]);
    TEST_ASSERT_EQUAL_DOUBLE(3.0, aenl_table_col(&t, 2)[0]);
    aenl_table_free(&t);
    (void)remove(path);
}

static void test_csv_missing_cells_are_nan_and_counted(void)
{
    aenl_table_t t;
    const char *path = tmp_path("missing.csv");
    write_text(path, "t,x,y\n1,,2\n2,nan,NaN\n3,4,\n4,5,6\n");
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &t, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_size_t(4, t.n_rows);
    TEST_ASSERT_EQUAL_size_t(0, t.n_nan[0]);
    TEST_ASSERT_EQUAL_size_t(2, t.n_nan[1]);
    TEST_ASSERT_EQUAL_size_t(2, t.n_nan[2]);
    TEST_ASSERT_EQUAL_DOUBLE(6.0, aenl_table_col(&t, 2)[3]);
    aenl_table_free(&t);
    (void)remove(path);
}

static void test_csv_header_only_gives_zero_rows(void)
{
    aenl_table_t t;
    const char *path = tmp_path("header_only.csv");
    write_text(path, "t,x\n# nothing yet\n\n");
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &t, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_size_t(0, t.n_rows);
    TEST_ASSERT_EQUAL_size_t(2, t.n_cols);
    TEST_ASSERT_EQUAL_STRING("x", t.names[1]);
    TEST_ASSERT_EQUAL_size_t(0, t.n_nan[1]);
    aenl_table_free(&t);
    (void)remove(path);
}

static void test_csv_skips_comments_and_blank_lines_counting_them(void)
{
    aenl_csv_t *csv = NULL;
    double row[2];
    const char *path = tmp_path("comments.csv");
    write_text(path, "# recorded 2024\n\nt,x\n  # a note\n1,2\n\n   \n3,4\n5,oops\n");
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_csv_open(&csv, path, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_UINT32(3, (uint32_t)aenl_csv_line(csv));
    TEST_ASSERT_EQUAL_INT(1, aenl_csv_next(csv, row, &g_err));
    TEST_ASSERT_EQUAL_UINT32(5, (uint32_t)aenl_csv_line(csv));
    TEST_ASSERT_EQUAL_DOUBLE(2.0, row[1]);
    TEST_ASSERT_EQUAL_INT(1, aenl_csv_next(csv, row, &g_err));
    TEST_ASSERT_EQUAL_UINT32(8, (uint32_t)aenl_csv_line(csv));
    TEST_ASSERT_EQUAL_DOUBLE(4.0, row[1]);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_csv_next(csv, row, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "comments.csv:9:2 (x): not a number 'oops'"),
                                 g_err.msg);
    /* Sticky: a later call fails too, never returns a row after an error. */
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_csv_next(csv, row, NULL));
    aenl_csv_close(csv);
    (void)remove(path);
}

static void test_csv_long_lines(void)
{
    const size_t n_cols = 5000;
    size_t c;
    char *text;
    size_t pos = 0;
    size_t cap = n_cols * 48 + 64;
    aenl_table_t t;
    const char *path = tmp_path("wide.csv");
    text = (char *)malloc(cap);
    TEST_ASSERT_NOT_NULL(text);
    for (c = 0; c < n_cols; ++c)
    {
        pos += (size_t)snprintf(text + pos, cap - pos, "column_with_a_long_name_%05lu%c",
                                (unsigned long)c, c + 1 < n_cols ? ',' : '\n');
    }
    for (c = 0; c < n_cols; ++c)
    {
        pos += (size_t)snprintf(text + pos, cap - pos, "%.17g%c", 0.001 * (double)c,
                                c + 1 < n_cols ? ',' : '\n');
    }
    write_bytes(path, text, pos);
    free(text);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &t, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_size_t(n_cols, t.n_cols);
    TEST_ASSERT_EQUAL_size_t(1, t.n_rows);
    TEST_ASSERT_EQUAL_STRING("column_with_a_long_name_04999", t.names[4999]);
    TEST_ASSERT_EQUAL_DOUBLE(0.001 * 4999.0, aenl_table_col(&t, 4999)[0]);
    aenl_table_free(&t);
    (void)remove(path);
}

/* ---- every error kind, with file:line:column --------------------------------------------- */

static void test_csv_error_not_a_number(void)
{
    const char *s = "t,alpha,beta\n1,2,3\n# c\n4,x1,6\n";
    expect_read_error("nan1.csv", s, strlen(s), AENL_E_ARG,
                      "nan1.csv:4:2 (alpha): not a number 'x1'");
}

/* A row of units under the header is named as such, whether its units are bare words or in
 * brackets or parentheses; a bracketed cell further down is only not a number. */
static void test_csv_error_unit_row(void)
{
    static const char *const rows[] = {"s,rad,m", "[s],[rad],[-]", "(s),(rad),(m)", "[ s ],[],[]"};
    for (size_t i = 0; i < sizeof(rows) / sizeof(rows[0]); ++i)
    {
        char text[128];
        char want[128];
        const char *cell_end = strchr(rows[i], ',');
        (void)snprintf(text, sizeof(text), "t,alpha,xi\n%s\n0,1,2\n", rows[i]);
        (void)snprintf(want, sizeof(want),
                       "units.csv:2:1 (t): not a number '%.*s' (a row of units?",
                       (int)(cell_end - rows[i]), rows[i]);
        expect_read_error("units.csv", text, strlen(text), AENL_E_ARG, want);
    }
    const char *later = "t,alpha\n0,1\n[s],2\n";
    expect_read_error("units.csv", later, strlen(later), AENL_E_ARG,
                      "units.csv:3:1 (t): not a number '[s]'");
    TEST_ASSERT_NULL_MESSAGE(strstr(g_err.msg, "row of units"), g_err.msg);
}

static void test_csv_error_trailing_garbage(void)
{
    const char *s = "t,alpha\n1,1.5x\n";
    expect_read_error("garbage.csv", s, strlen(s), AENL_E_ARG,
                      "garbage.csv:2:2 (alpha): not a number '1.5x'");
}

static void test_csv_error_inf(void)
{
    const char *s1 = "t,x,y\n1,2,inf\n";
    const char *s2 = "t,x,y\n1,2,3\n2,-inf,3\n";
    const char *s3 = "t,x,y\n1,2,1e999\n";
    expect_read_error("inf1.csv", s1, strlen(s1), AENL_E_NUMERIC,
                      "inf1.csv:2:3 (y): infinite value 'inf'");
    expect_read_error("inf2.csv", s2, strlen(s2), AENL_E_NUMERIC,
                      "inf2.csv:3:2 (x): infinite value '-inf'");
    expect_read_error("inf3.csv", s3, strlen(s3), AENL_E_NUMERIC,
                      "inf3.csv:2:3 (y): number out of range '1e999'");
}

static void test_csv_error_ragged_rows(void)
{
    const char *few = "t,x,y\n1,2,3\n4,5\n";
    const char *many = "t,x\n1,2\n\n3,4,5,6\n";
    expect_read_error("few.csv", few, strlen(few), AENL_E_ARG,
                      "few.csv:3:3 (y): missing cell (row has 2 cells, header has 3)");
    expect_read_error("many.csv", many, strlen(many), AENL_E_ARG,
                      "many.csv:4:3: extra cell (row has 4 cells, header has 2)");
}

static void test_csv_error_bad_header(void)
{
    const char *dup = "# header follows\nt,x,x\n1,2,3\n";
    const char *empty = "t,,x\n1,2,3\n";
    const char *trailing = "t,x,\n1,2,3\n";
    expect_read_error("dup.csv", dup, strlen(dup), AENL_E_ARG,
                      "dup.csv:2:3 (x): duplicate column name 'x' (also column 2)");
    expect_read_error("emptyname.csv", empty, strlen(empty), AENL_E_ARG,
                      "emptyname.csv:1:2: empty column name");
    expect_read_error("trailing.csv", trailing, strlen(trailing), AENL_E_ARG,
                      "trailing.csv:1:3: empty column name");
}

static void test_csv_error_empty_file(void)
{
    aenl_csv_t *csv = NULL;
    const char *path = tmp_path("empty.csv");
    write_text(path, "");
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_csv_open(&csv, path, &g_err));
    TEST_ASSERT_NULL(csv);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "empty.csv: empty file (no header row)"),
                                 g_err.msg);
    (void)remove(path);
    expect_read_error("comments_only.csv", "# a\n\n# b\n", 9, AENL_E_EMPTY,
                      "comments_only.csv: empty file (no header row");
}

static void test_csv_error_binary_line(void)
{
    const char nul[] = "t,x\n1,2\n3,\0\n";
    const char ctl[] = "t,x\n1,2\n3,4\n5,\x01\x02\n";
    expect_read_error("nul.csv", nul, sizeof nul - 1, AENL_E_ARG,
                      "nul.csv:3: NUL byte at character 3");
    expect_read_error("ctl.csv", ctl, sizeof ctl - 1, AENL_E_ARG, "ctl.csv:4: control byte 0x01");
}

/* A control byte (a line feed ends the line) anywhere in a long line (the scan takes 8 bytes at a
 * time: every position in and between words, every control value) is reported at its own position;
 * tabs, bytes of 0x80 and above and printable bytes next to it are not. */
static void test_csv_control_byte_any_position(void)
{
    char text[128], want[96];
    for (unsigned v = 0; v < 0x80u; ++v)
    {
        const int bad = v == 0x7Fu || (v < 0x20u && v != (unsigned)'\t' && v != (unsigned)'\n');
        if (!bad)
        {
            continue;
        }
        for (size_t pos = 2; pos < 42; ++pos)
        {
            /* line 2: a comment of 44 bytes of 0x7E, 0x80, 0xFF and spaces, a tab last */
            memcpy(text, "t,x\n", sizeof("t,x\n")); /* its NUL is overwritten below */
            char *line = text + 4;
            line[0] = '#';
            line[1] = ' ';
            for (size_t i = 2; i < 44; ++i)
            {
                static const char fill[4] = {'~', (char)0x80, (char)0xFF, ' '};
                line[i] = fill[i % 4u];
            }
            line[43] = '\t';
            line[pos] = (char)v;
            memcpy(line + 44, "\n1,2\n", 6);
            if (v == 0u)
            {
                (void)snprintf(want, sizeof(want), "ctl.csv:2: NUL byte at character %zu", pos + 1);
            }
            else
            {
                (void)snprintf(want, sizeof(want),
                               "ctl.csv:2: control byte 0x%02x at character %zu", v, pos + 1);
            }
            expect_read_error("ctl.csv", text, 4 + 44 + 5, AENL_E_ARG, want);
        }
    }
    /* the same line without a control byte reads */
    aenl_table_t t;
    const char *path = tmp_path("clean.csv");
    memcpy(text, "t,x\n# ", sizeof("t,x\n# "));
    for (size_t i = 2; i < 44; ++i)
    {
        static const char fill[4] = {'~', (char)0x80, (char)0xFF, ' '};
        text[4 + i] = fill[i % 4u];
    }
    text[4 + 43] = '\t';
    memcpy(text + 48, "\n1,2\n", 6);
    write_bytes(path, text, 53);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &t, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_size_t(1, t.n_rows);
    aenl_table_free(&t);
    (void)remove(path);
}

static void test_csv_error_missing_file(void)
{
    aenl_table_t t;
    const char *path = tmp_path("no_such_file.csv");
    TEST_ASSERT_EQUAL_INT(AENL_E_IO, aenl_table_read(path, &t, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "no_such_file.csv: cannot open"), g_err.msg);
}

/* ---- a long file, streamed ----------------------------------------------------------------- */

static void test_csv_streams_a_million_rows(void)
{
    const unsigned long n_rows = 1000000UL;
    unsigned long i;
    FILE *fp;
    aenl_csv_t *csv = NULL;
    double row[3];
    double sum = 0.0;
    unsigned long n = 0;
    int rc;
    clock_t t0;
    char msg[128];
    const char *path = tmp_path("million.csv");
    fp = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(fp);
    fputs("t,x,y\n", fp);
    for (i = 0; i < n_rows; ++i)
    {
        fprintf(fp, "%lu,%.17g,%s\n", i, 0.25 * (double)(i % 8), (i % 1000 == 0) ? "" : "1");
    }
    TEST_ASSERT_EQUAL_INT(0, fclose(fp));
    t0 = clock();
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_csv_open(&csv, path, &g_err));
    while ((rc = aenl_csv_next(csv, row, &g_err)) == 1)
    {
        sum += row[1];
        n += isnan(row[2]) ? 1UL : 0UL;
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, g_err.msg);
    TEST_ASSERT_EQUAL_UINT32(1000001UL, (uint32_t)aenl_csv_line(csv));
    aenl_csv_close(csv);
    (void)snprintf(msg, sizeof msg, "streamed 10^6 rows in %.2f s",
                   (double)(clock() - t0) / (double)CLOCKS_PER_SEC);
    TEST_MESSAGE(msg);
    const size_t n_blocks = n_rows / 8; /* whole blocks of 8 rows */
    TEST_ASSERT_EQUAL_DOUBLE(0.25 * 28.0 * (double)n_blocks, sum);
    TEST_ASSERT_EQUAL_UINT32(1000, (uint32_t)n);
    (void)remove(path);
}

/* ---- atomic output files ------------------------------------------------------------------- */

static void test_outfile_not_visible_before_commit(void)
{
    aenl_outfile_t of;
    const char *path = tmp_path("atomic.txt");
    char buf[32] = {0};
    FILE *fp;
    (void)remove(path);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_outfile_open(&of, path, &g_err));
    TEST_ASSERT_NOT_NULL(of.fp);
    fputs("hello\n", of.fp);
    TEST_ASSERT_FALSE(file_exists(path));
    TEST_ASSERT_TRUE(file_exists(of.tmp_path));
    TEST_ASSERT_EQUAL_INT(1, count_entries_with(".atomic.txt.tmp."));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_outfile_commit(&of, &g_err));
    TEST_ASSERT_NULL(of.fp);
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    fp = fopen(path, "r");
    TEST_ASSERT_NOT_NULL(fp);
    TEST_ASSERT_NOT_NULL(fgets(buf, sizeof buf, fp));
    (void)fclose(fp);
    TEST_ASSERT_EQUAL_STRING("hello\n", buf);
    aenl_outfile_abort(&of); /* safe on a committed outfile: must not remove the result */
    TEST_ASSERT_TRUE(file_exists(path));
    (void)remove(path);
}

static void test_outfile_abort_leaves_no_file(void)
{
    aenl_outfile_t of;
    aenl_outfile_t zero;
    const char *path = tmp_path("aborted.txt");
    memset(&zero, 0, sizeof zero);
    aenl_outfile_abort(&zero); /* safe on a zeroed outfile */
    aenl_outfile_abort(NULL);
    (void)remove(path);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_outfile_open(&of, path, &g_err));
    fputs("partial", of.fp);
    aenl_outfile_abort(&of);
    aenl_outfile_abort(&of); /* twice */
    TEST_ASSERT_FALSE(file_exists(path));
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
}

static void test_outfile_existing_file_kept_until_commit(void)
{
    aenl_outfile_t of;
    const char *path = tmp_path("keep.txt");
    char buf[32] = {0};
    FILE *fp;
    write_text(path, "old\n");
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_outfile_open(&of, path, &g_err));
    fputs("new\n", of.fp);
    aenl_outfile_abort(&of);
    fp = fopen(path, "r");
    TEST_ASSERT_NOT_NULL(fp);
    TEST_ASSERT_NOT_NULL(fgets(buf, sizeof buf, fp));
    (void)fclose(fp);
    TEST_ASSERT_EQUAL_STRING("old\n", buf);
    (void)remove(path);
}

/* The first line of path into buf (empty when it cannot be read). */
static void first_line(const char *path, char *buf, size_t n)
{
    FILE *fp = fopen(path, "r");
    buf[0] = '\0';
    if (fp != NULL)
    {
        if (fgets(buf, (int)n, fp) == NULL)
        {
            buf[0] = '\0';
        }
        (void)fclose(fp);
    }
}

static aenl_status_t commit_text(const char *path, const char *text)
{
    aenl_outfile_t of;
    aenl_status_t st = aenl_outfile_open(&of, path, &g_err);
    if (st == AENL_OK)
    {
        fputs(text, of.fp);
        st = aenl_outfile_commit(&of, &g_err);
    }
    return st;
}

/* A run that fails puts back every file its commits replaced and removes the ones they made; a
 * run that succeeds keeps its outputs and leaves no copy of what they replaced. */
static void test_outfile_run_failure_restores_files(void)
{
    char old[1024], fresh[1024], buf[32];
    (void)snprintf(old, sizeof old, "%s", tmp_path("run_old.txt"));
    (void)snprintf(fresh, sizeof fresh, "%s", tmp_path("run_fresh.txt"));
    write_text(old, "old\n");
    (void)remove(fresh);
    aenl_outfile_run_begin();
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, commit_text(old, "new\n"), g_err.msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, commit_text(fresh, "fresh\n"), g_err.msg);
    first_line(old, buf, sizeof buf);
    TEST_ASSERT_EQUAL_STRING("new\n", buf); /* in place while the run goes on */
    TEST_ASSERT_EQUAL_INT(1, count_entries_with(".run_old.txt.bak."));
    aenl_outfile_abort_all(); /* the run failed */
    first_line(old, buf, sizeof buf);
    TEST_ASSERT_EQUAL_STRING("old\n", buf);
    TEST_ASSERT_FALSE(file_exists(fresh));
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".bak."));
    aenl_outfile_run_keep();
    /* the same, succeeding */
    aenl_outfile_run_begin();
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, commit_text(old, "new\n"), g_err.msg);
    aenl_outfile_run_keep();
    aenl_outfile_abort_all(); /* after the run: nothing to undo */
    first_line(old, buf, sizeof buf);
    TEST_ASSERT_EQUAL_STRING("new\n", buf);
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".bak."));
    (void)remove(old);
}

/* Inside a run no output replaces an input (by any path: a symbolic or a hard link is the same
 * file), nor another output of the run (by any spelling of its path). */
static void test_outfile_run_refuses_inputs_and_repeats(void)
{
    char in[1024], sym[1024], hard[1024], out[1024], out2[1024], late[1024], buf[32];
    aenl_outfile_t of;
    (void)snprintf(in, sizeof in, "%s", tmp_path("run_in.csv"));
    (void)snprintf(sym, sizeof sym, "%s", tmp_path("run_in_sym.csv"));
    (void)snprintf(hard, sizeof hard, "%s", tmp_path("run_in_hard.csv"));
    (void)snprintf(out, sizeof out, "%s", tmp_path("run_out.txt"));
    (void)snprintf(out2, sizeof out2, "%s/./run_out.txt", AENL_TEST_TMP_DIR);
    (void)snprintf(late, sizeof late, "%s", tmp_path("run_late.txt"));
    write_text(in, "t,x\n0,1\n");
    (void)remove(sym);
    (void)remove(hard);
    (void)remove(out);
    TEST_ASSERT_EQUAL_INT(0, symlink(in, sym));
    TEST_ASSERT_EQUAL_INT(0, link(in, hard));
    aenl_outfile_run_begin();
    aenl_input_note(in);
    const char *const as_input[] = {in, sym, hard};
    for (size_t i = 0; i < 3; ++i)
    {
        aenl_err_clear(&g_err);
        TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_outfile_open(&of, as_input[i], &g_err));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "is an input of this run"), g_err.msg);
    }
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, commit_text(out, "one\n"), g_err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_outfile_open(&of, out2, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "already an output of this run"), g_err.msg);
    /* a file read after its output was opened is refused at the commit, and kept as it was */
    write_text(late, "late\n");
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_outfile_open(&of, late, &g_err));
    fputs("replaced\n", of.fp);
    aenl_input_note(late);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_outfile_commit(&of, &g_err));
    first_line(late, buf, sizeof buf);
    TEST_ASSERT_EQUAL_STRING("late\n", buf);
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    aenl_outfile_run_keep();
    /* outside a run the library writes where it is told */
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, commit_text(out2, "two\n"), g_err.msg);
    (void)remove(in);
    (void)remove(sym);
    (void)remove(hard);
    (void)remove(out);
    (void)remove(late);
}

/* A figure is complete when it ends as its format does; a full disk leaves gnuplot's file empty
 * or cut short, and such a file must not replace anything. */
static void test_figure_cut_short_is_incomplete(void)
{
    static const unsigned char png[] = {0x89, 'P',  'N',  'G',  0x0D, 0x0A, 0x1A, 0x0A, 0x00, 0x00,
                                        0x00, 0x00, 0x49, 0x45, 0x4E, 0x44, 0xAE, 0x42, 0x60, 0x82};
    static const char svg[] = "<?xml version=\"1.0\"?>\n<svg>\n<g/>\n</svg>\n\n";
    static const char pdf[] = "%PDF-1.4\n1 0 obj\n<<>>\nendobj\ntrailer\n<<>>\n%%EOF\n";
    const struct
    {
        const char *fmt;
        const void *bytes;
        size_t n;
        size_t cut; /* bytes left when cut short */
    } k[] = {{"png", png, sizeof(png), sizeof(png) - 1u},
             {"svg", svg, sizeof(svg) - 1u, sizeof(svg) - 9u},
             {"pdf", pdf, sizeof(pdf) - 1u, sizeof(pdf) - 4u}};
    char path[1024];
    (void)snprintf(path, sizeof path, "%s", tmp_path("figure.bin"));
    for (size_t i = 0; i < sizeof(k) / sizeof(k[0]); ++i)
    {
        write_bytes(path, k[i].bytes, k[i].n);
        TEST_ASSERT_EQUAL_INT_MESSAGE(1, aenl_plot_file_complete(path, k[i].fmt), k[i].fmt);
        write_bytes(path, k[i].bytes, k[i].cut);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, aenl_plot_file_complete(path, k[i].fmt), k[i].fmt);
        write_bytes(path, k[i].bytes, 0);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, aenl_plot_file_complete(path, k[i].fmt), k[i].fmt);
    }
    (void)remove(path);
    TEST_ASSERT_EQUAL_INT(0, aenl_plot_file_complete(path, "png")); /* no file */
}

static void test_outfile_missing_folder_fails_cleanly(void)
{
    aenl_outfile_t of;
    aenl_table_t t;
    const char *names[] = {"t"};
    char path[1024];
    (void)snprintf(path, sizeof path, "%s/no_such_dir/out.csv", AENL_TEST_TMP_DIR);
    TEST_ASSERT_EQUAL_INT(AENL_E_IO, aenl_outfile_open(&of, path, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "no_such_dir/out.csv: cannot create"),
                                 g_err.msg);
    TEST_ASSERT_NULL(of.fp);
    TEST_ASSERT_NULL(of.tmp_path);
    aenl_outfile_abort(&of);
    /* Through the table writer as well. */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_table_alloc(&t, 3, 1, names, &g_err));
    TEST_ASSERT_EQUAL_size_t(3, t.n_nan[0]);
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_INT(AENL_E_IO, aenl_table_write(&t, path, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "no_such_dir/out.csv"), g_err.msg);
    aenl_table_free(&t);
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
}

static void test_outfile_commit_failure_removes_temporary(void)
{
    aenl_outfile_t of;
    char path[1024];
    char inner[1100];
    (void)snprintf(path, sizeof path, "%s", tmp_path("is_a_dir"));
    (void)snprintf(inner, sizeof inner, "%s/child", path);
    (void)remove(inner);
    (void)rmdir(path);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_outfile_open(&of, path, &g_err));
    fputs("data\n", of.fp);
    /* A non-empty folder takes the name while the file is written: rename over it must fail. */
    TEST_ASSERT_EQUAL_INT(0, mkdir(path, 0777));
    write_text(inner, "x");
    TEST_ASSERT_EQUAL_INT(AENL_E_IO, aenl_outfile_commit(&of, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "is_a_dir: cannot rename into place"),
                                 g_err.msg);
    TEST_ASSERT_NULL(of.fp);
    TEST_ASSERT_NULL(of.tmp_path);
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    /* A folder named as the output is refused at open, before anything is written. */
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_outfile_open(&of, path, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "is a folder"), g_err.msg);
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    (void)remove(inner);
    (void)rmdir(path);
}

static void read_first_line(const char *path, char *buf, size_t n)
{
    FILE *fp = fopen(path, "r");
    TEST_ASSERT_NOT_NULL_MESSAGE(fp, path);
    buf[0] = '\0';
    TEST_ASSERT_NOT_NULL(fgets(buf, (int)n, fp));
    (void)fclose(fp);
}

static void write_through(const char *path, const char *text)
{
    aenl_outfile_t of;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_outfile_open(&of, path, &g_err), g_err.msg);
    fputs(text, of.fp);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_outfile_commit(&of, &g_err), g_err.msg);
}

/* A character device is written, never replaced. As root a private twin of /dev/null (1, 3) is
 * made here, so a regression cannot replace the system's; where root cannot make or open one
 * (no mknod capability, a nodev file system) the case is skipped rather than run on the system's.
 * Without root /dev/null itself is used, which a regression could not replace (its folder is not
 * writable). */
static void test_outfile_device_written_not_replaced(void)
{
    struct stat before;
    struct stat after;
    char own[1024];
    (void)snprintf(own, sizeof own, "%s", tmp_path("null_twin"));
    const char *dev = aenl_test_null_device(own);
    TEST_ASSERT_EQUAL_INT(0, stat(dev, &before));
    TEST_ASSERT_TRUE(S_ISCHR(before.st_mode));
    write_through(dev, "discarded\n");
    TEST_ASSERT_EQUAL_INT(0, lstat(dev, &after));
    TEST_ASSERT_TRUE_MESSAGE(S_ISCHR(after.st_mode), "the device was replaced");
    TEST_ASSERT_EQUAL_UINT64((uint64_t)before.st_ino, (uint64_t)after.st_ino);
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    (void)remove(own);
}

/* A FIFO is opened and written as it is: the reader gets the bytes, the FIFO stays. */
static void test_outfile_fifo_written_not_replaced(void)
{
    char fifo[1024];
    char got[1024];
    char line[64];
    struct stat st;
    pid_t pid;
    int status = -1;
    (void)snprintf(fifo, sizeof fifo, "%s", tmp_path("out.fifo"));
    (void)snprintf(got, sizeof got, "%s", tmp_path("fifo_got.txt"));
    (void)remove(fifo);
    (void)remove(got);
    TEST_ASSERT_EQUAL_INT(0, mkfifo(fifo, 0600));
    pid = fork();
    TEST_ASSERT_TRUE(pid >= 0);
    if (pid == 0)
    {
        /* The reader copies what arrives into a file; it exits with the test's verdict. */
        char buf[256];
        size_t n;
        FILE *in = fopen(fifo, "r");
        FILE *out = fopen(got, "w");
        if (in == NULL || out == NULL)
        {
            _exit(1);
        }
        while ((n = fread(buf, 1, sizeof buf, in)) > 0)
        {
            (void)fwrite(buf, 1, n, out);
        }
        _exit((fclose(in) == 0 && fclose(out) == 0) ? 0 : 1);
    }
    write_through(fifo, "through the fifo\n");
    TEST_ASSERT_EQUAL_INT(pid, waitpid(pid, &status, 0));
    TEST_ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    TEST_ASSERT_EQUAL_INT(0, lstat(fifo, &st));
    TEST_ASSERT_TRUE_MESSAGE(S_ISFIFO(st.st_mode), "the FIFO was replaced");
    read_first_line(got, line, sizeof line);
    TEST_ASSERT_EQUAL_STRING("through the fifo\n", line);
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    (void)remove(fifo);
    (void)remove(got);
}

/* A symbolic link is followed: the file it names is replaced, the link stays a link, and a
 * dangling link creates the file it names. The replaced file keeps its permissions. */
static void test_outfile_symlink_written_through(void)
{
    char real[1024];
    char link_path[1024];
    char dangling[1024];
    char made[1024];
    char line[64];
    struct stat st;
    (void)snprintf(real, sizeof real, "%s", tmp_path("real.txt"));
    (void)snprintf(link_path, sizeof link_path, "%s", tmp_path("link.txt"));
    (void)snprintf(dangling, sizeof dangling, "%s", tmp_path("dangling.txt"));
    (void)snprintf(made, sizeof made, "%s", tmp_path("made.txt"));
    (void)remove(link_path);
    (void)remove(dangling);
    (void)remove(made);
    write_text(real, "old\n");
    TEST_ASSERT_EQUAL_INT(0, chmod(real, 0640));
    TEST_ASSERT_EQUAL_INT(0, symlink("real.txt", link_path)); /* relative to the link's folder */
    TEST_ASSERT_EQUAL_INT(0, symlink("made.txt", dangling));
    write_through(link_path, "new\n");
    TEST_ASSERT_EQUAL_INT(0, lstat(link_path, &st));
    TEST_ASSERT_TRUE_MESSAGE(S_ISLNK(st.st_mode), "the link was replaced");
    read_first_line(real, line, sizeof line);
    TEST_ASSERT_EQUAL_STRING("new\n", line);
    TEST_ASSERT_EQUAL_INT(0, stat(real, &st));
    TEST_ASSERT_EQUAL_UINT(0640U, (unsigned)(st.st_mode & 07777));
    write_through(dangling, "created\n");
    TEST_ASSERT_EQUAL_INT(0, lstat(dangling, &st));
    TEST_ASSERT_TRUE(S_ISLNK(st.st_mode));
    read_first_line(made, line, sizeof line);
    TEST_ASSERT_EQUAL_STRING("created\n", line);
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    (void)remove(link_path);
    (void)remove(dangling);
    (void)remove(made);
    (void)remove(real);
}

/* Places nothing may be written to fail at open with the path named, whoever runs the test:
 * a file system that refuses new files even to root, and (without root) a read-only file. */
static void test_outfile_unwritable_fails_cleanly(void)
{
    aenl_outfile_t of;
    char ro[1024];
    TEST_ASSERT_EQUAL_INT(AENL_E_IO, aenl_outfile_open(&of, "/proc/aenl_out.csv", &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "/proc/aenl_out.csv: cannot"), g_err.msg);
    TEST_ASSERT_NULL(of.fp);
    aenl_outfile_abort(&of);
    (void)snprintf(ro, sizeof ro, "%s", tmp_path("read_only.txt"));
    write_text(ro, "keep\n");
    TEST_ASSERT_EQUAL_INT(0, chmod(ro, 0444));
    if (geteuid() != 0)
    {
        char line[64];
        aenl_err_clear(&g_err);
        TEST_ASSERT_EQUAL_INT(AENL_E_IO, aenl_outfile_open(&of, ro, &g_err));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "read_only.txt: cannot write"), g_err.msg);
        read_first_line(ro, line, sizeof line);
        TEST_ASSERT_EQUAL_STRING("keep\n", line);
    }
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    (void)chmod(ro, 0644);
    (void)remove(ro);
}

static void test_outfile_abort_all_removes_pending(void)
{
    aenl_outfile_t a;
    aenl_outfile_t b;
    char pa[1024];
    char pb[1024];
    (void)snprintf(pa, sizeof pa, "%s", tmp_path("pending_a.txt"));
    (void)snprintf(pb, sizeof pb, "%s", tmp_path("pending_b.txt"));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_outfile_open(&a, pa, &g_err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_outfile_open(&b, pb, &g_err));
    TEST_ASSERT_EQUAL_INT(2, count_entries_with(".tmp."));
    aenl_outfile_abort_all();
    TEST_ASSERT_EQUAL_INT(0, count_entries_with(".tmp."));
    aenl_outfile_abort(&a); /* still safe afterwards; frees */
    aenl_outfile_abort(&b);
    TEST_ASSERT_FALSE(file_exists(pa));
    TEST_ASSERT_FALSE(file_exists(pb));
}

/* aenl's own files: $AENL_SHARE_DIR is looked in first; a file that is nowhere is an error that
 * names it, with an empty path. */
static void test_share_path_order_and_error(void)
{
    char dir[] = "./share_test_XXXXXX";
    TEST_ASSERT_NOT_NULL(mkdtemp(dir));
    char sub[64], file[96];
    (void)snprintf(sub, sizeof(sub), "%s/plot", dir);
    (void)snprintf(file, sizeof(file), "%s/plot/probe.gp", dir);
    TEST_ASSERT_EQUAL_INT(0, mkdir(sub, 0700));
    FILE *f = fopen(file, "w");
    TEST_ASSERT_NOT_NULL(f);
    (void)fclose(f);
    TEST_ASSERT_EQUAL_INT(0, setenv("AENL_SHARE_DIR", dir, 1));
    char buf[512];
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_share_path("plot/probe.gp", buf, sizeof(buf), &err));
    TEST_ASSERT_EQUAL_STRING(file, buf);
    TEST_ASSERT_EQUAL_INT(AENL_E_IO, aenl_share_path("plot/absent.gp", buf, sizeof(buf), &err));
    TEST_ASSERT_EQUAL_STRING("", buf);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "plot/absent.gp"), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, dir + 2), err.msg);
    TEST_ASSERT_EQUAL_INT(0, unsetenv("AENL_SHARE_DIR"));
    TEST_ASSERT_EQUAL_INT(0, remove(file));
    TEST_ASSERT_EQUAL_INT(0, rmdir(sub));
    TEST_ASSERT_EQUAL_INT(0, rmdir(dir));
}

/* Time column names: the bases t, time, tau, timestamp in any case, with a unit of time. */
static void test_csv_time_names(void)
{
    const char *yes[] = {"t",        "T",      "time",       "Time [s]", "time_s",
                         "t (s)",    "t(s)",   "TIMESTAMP",  "tau",      "time (ms)",
                         "Time_sec", "t [us]", "timestamp_s"};
    const char *no[] = {"theta",  "t_alpha", "timex", "tau2",     "alpha", "time [m]",
                        "time (", "t []",    "",      "time_s_2", "tt",    "xi"};
    for (size_t i = 0; i < sizeof(yes) / sizeof(yes[0]); ++i)
    {
        TEST_ASSERT_TRUE_MESSAGE(aenl_csv_is_time_name(yes[i]), yes[i]);
    }
    for (size_t i = 0; i < sizeof(no) / sizeof(no[0]); ++i)
    {
        TEST_ASSERT_FALSE_MESSAGE(aenl_csv_is_time_name(no[i]), no[i]);
    }
}

/* Uniform sampling: exact steps, times rounded to 1e-5 s at 1024 Hz (steps 8 % apart) and
 * 2048 Hz printed with %g pass; a dropout and +-20 % jitter are caught at their row, with the
 * step and the reference. */
static void test_time_steps(void)
{
    aenl_time_steps_t s;
    double step = 0.0;
    double ref = 0.0;
    memset(&s, 0, sizeof(s));
    for (int k = 0; k < 30000; ++k)
    {
        const double t = floor((double)k / 1024.0 * 1e5 + 0.5) / 1e5;
        TEST_ASSERT_TRUE(aenl_time_steps_take(&s, t, &step, &ref));
    }
    /* 2048 Hz for 12 s printed with six significant digits (%g): 1e-4 s past 10 s */
    memset(&s, 0, sizeof(s));
    for (int k = 0; k < 24576; ++k)
    {
        char txt[32];
        (void)snprintf(txt, sizeof(txt), "%g", (double)k / 2048.0);
        TEST_ASSERT_TRUE_MESSAGE(aenl_time_steps_take(&s, strtod(txt, NULL), &step, &ref), txt);
    }
    memset(&s, 0, sizeof(s));
    int bad = -1;
    for (int k = 0; k < 1000 && bad < 0; ++k)
    {
        const double t = 0.002 * (double)k + (k >= 500 ? 1.0 : 0.0);
        bad = aenl_time_steps_take(&s, t, &step, &ref) ? -1 : k;
    }
    TEST_ASSERT_EQUAL_INT(500, bad);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 1.002, step);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.002, ref);
    memset(&s, 0, sizeof(s));
    bad = -1;
    for (int k = 0; k < 1000 && bad < 0; ++k)
    {
        const double t = 0.002 * (double)k + ((k % 2) ? 0.0004 : 0.0);
        bad = aenl_time_steps_take(&s, t, &step, &ref) ? -1 : k;
    }
    TEST_ASSERT_EQUAL_INT(2, bad);
}

/* The check of uniform sampling written out as its definition: every value's decimals found by
 * trying 0, 1, ... 17, the finest resolution and the most significant digits kept, and the
 * rounding bound computed at every step. */
typedef struct
{
    double t0, t_prev, q_dec;
    size_t k;
    int digits;
} ref_steps_t;

static double ref_rounding(const ref_steps_t *s, double t)
{
    if (!(fabs(t) > 0.0))
    {
        return 0.0;
    }
    return fmax(s->q_dec, pow(10.0, floor(log10(fabs(t))) - (double)s->digits + 1.0));
}

static int ref_steps_take(ref_steps_t *s, double t, double *step, double *ref)
{
    if (fabs(t) > 0.0)
    {
        double p = 1.0;
        for (int k = 0; k <= 17; ++k)
        {
            const double v = t * p;
            if (fabs(v - nearbyint(v)) <= 1e-9 * fmax(1.0, fabs(v)))
            {
                const double q = 1.0 / p;
                s->q_dec = s->q_dec > 0.0 ? fmin(s->q_dec, q) : q;
                const int d = (int)floor(log10(fabs(t))) - (int)lround(log10(q)) + 1;
                s->digits = d > s->digits ? d : s->digits;
                break;
            }
            p *= 10.0;
        }
    }
    int ok = 1;
    if (s->k == 0)
    {
        s->t0 = t;
    }
    else if (s->k >= 2)
    {
        *step = t - s->t_prev;
        *ref = (s->t_prev - s->t0) / (double)(s->k - 1u);
        const double rounding = ref_rounding(s, t) + ref_rounding(s, s->t_prev);
        ok = *step <= AENL_TIME_GAP * *ref &&
             fabs(*step - *ref) <= fmax(AENL_TIME_STEP_TOL * *ref, rounding);
    }
    s->t_prev = t;
    s->k++;
    return ok;
}

/* The check against its definition on 400 records of 3 000 times: rates from 1 Hz to 100 kHz,
 * starts from -5 s to 10^4 s, printed with 4 to 17 significant digits (%g) or 0 to 9 decimals
 * (%f), some with jitter of up to 2 % of a step or with a gap; every value's verdict, step and
 * reference the same. */
static void test_time_steps_against_definition(void)
{
    uint64_t seed = 99u;
    size_t rejected = 0;
    for (int rec = 0; rec < 400; ++rec)
    {
        const double rate = pow(10.0, 5.0 * test_uniform(&seed));
        const double t_start = test_uniform(&seed) < 0.3
                                   ? -5.0 * test_uniform(&seed)
                                   : pow(10.0, 4.0 * test_uniform(&seed)) - 1.0;
        const int fixed = test_uniform(&seed) < 0.4;
        const int prec =
            fixed ? (int)(10.0 * test_uniform(&seed)) : 4 + (int)(14.0 * test_uniform(&seed));
        const double jitter = test_uniform(&seed) < 0.3 ? 0.02 * test_uniform(&seed) : 0.0;
        const int gap_at = test_uniform(&seed) < 0.2 ? (int)(3000.0 * test_uniform(&seed)) : -1;
        aenl_time_steps_t s;
        ref_steps_t r;
        memset(&s, 0, sizeof(s));
        memset(&r, 0, sizeof(r));
        for (int k = 0; k < 3000; ++k)
        {
            double t = t_start + ((double)k + jitter * (test_uniform(&seed) - 0.5)) / rate;
            t += (gap_at >= 0 && k >= gap_at) ? 3.0 / rate : 0.0;
            char txt[64];
            if (fixed)
            {
                (void)snprintf(txt, sizeof(txt), "%.*f", prec, t);
            }
            else
            {
                (void)snprintf(txt, sizeof(txt), "%.*g", prec, t);
            }
            const double v = strtod(txt, NULL);
            double step = 0.0;
            double ref = 0.0;
            double step_r = 0.0;
            double ref_r = 0.0;
            const int ok = aenl_time_steps_take(&s, v, &step, &ref);
            const int ok_r = ref_steps_take(&r, v, &step_r, &ref_r);
            TEST_ASSERT_EQUAL_INT_MESSAGE(ok_r, ok, txt);
            TEST_ASSERT_EQUAL_DOUBLE(step_r, step);
            TEST_ASSERT_EQUAL_DOUBLE(ref_r, ref);
            TEST_ASSERT_EQUAL_DOUBLE(r.q_dec, s.q_dec);
            TEST_ASSERT_EQUAL_INT(r.digits, s.digits);
            rejected += ok ? 0u : 1u;
        }
    }
    printf("time steps: %zu values rejected of 1 200 000, each as the definition does\n", rejected);
    TEST_ASSERT_TRUE(rejected > 0);
}

/* d's bits (the comparison is bit for bit: -0 and +0 differ) */
static uint64_t bits_of(double d)
{
    uint64_t b;
    memcpy(&b, &d, sizeof(b));
    return b;
}

/* The values a few units in the last place either side of 10^e, ascending, fed to both checks:
 * every verdict, the finest resolution and the most digits the same. */
static size_t decade_edge(aenl_time_steps_t *s, ref_steps_t *r, int e, double sign)
{
    char txt[16];
    (void)snprintf(txt, sizeof(txt), "1e%d", e);
    double v = strtod(txt, NULL);
    for (int i = 0; i < 4; ++i)
    {
        v = nextafter(v, 0.0);
    }
    size_t seen = 0;
    for (int i = 0; i < 9; ++i)
    {
        double step = 0.0;
        double ref = 0.0;
        double step_r = 0.0;
        double ref_r = 0.0;
        const int ok = aenl_time_steps_take(s, sign * v, &step, &ref);
        TEST_ASSERT_EQUAL_INT(ref_steps_take(r, sign * v, &step_r, &ref_r), ok);
        TEST_ASSERT_EQUAL_DOUBLE(r->q_dec, s->q_dec);
        TEST_ASSERT_EQUAL_INT(r->digits, s->digits);
        ++seen;
        v = nextafter(v, HUGE_VAL);
    }
    return seen;
}

/* Values around every power of ten from 1e-8 to 1e8 (where a decade's exponent is decided by
 * log10's rounding), ascending, then negative and descending, then near 1e+-300: the check's
 * verdicts, finest resolution and most digits are the definition's at every value. */
static void test_time_steps_decade_edges(void)
{
    aenl_time_steps_t s;
    ref_steps_t r;
    memset(&s, 0, sizeof(s));
    memset(&r, 0, sizeof(r));
    size_t seen = 0;
    for (int e = -8; e <= 8; ++e)
    {
        seen += decade_edge(&s, &r, e, 1.0);
    }
    memset(&s, 0, sizeof(s));
    memset(&r, 0, sizeof(r));
    for (int e = 8; e >= -8; --e)
    {
        seen += decade_edge(&s, &r, e, -1.0);
    }
    memset(&s, 0, sizeof(s));
    memset(&r, 0, sizeof(r));
    for (int e = -300; e <= 300; e += 600)
    {
        seen += decade_edge(&s, &r, e, 1.0);
        seen += decade_edge(&s, &r, e + 1, 1.0);
    }
    TEST_ASSERT_EQUAL_size_t(2u * 17u * 9u + 4u * 9u, seen);
}

/* A record whose first lines are longer (long_first) or shorter than the rest, so that the
 * reader's guess of its rows from the file's size and its first lines is too low or too high;
 * row k holds k, 1e-3 k and -k / 7, written to round trip. */
static void write_uneven(const char *path, int long_first, long rows)
{
    FILE *fp = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL(fp);
    (void)fputs("t,a,b\n", fp);
    for (long k = 0; k < rows; ++k)
    {
        const int first = k < 3000;
        const int pad = (first == long_first) ? 40 : 0;
        (void)fprintf(fp, "%ld,%*s%.17g,%.17g\n", k, pad, "", 1e-3 * (double)k, -(double)k / 7.0);
    }
    TEST_ASSERT_EQUAL_INT(0, fclose(fp));
}

/* A table sized ahead from its first lines holds every row when the guess is too low (it grows)
 * and when it is too high (it shrinks), each value as written; a large file of no data row is
 * an empty table. */
static void test_table_read_sized_ahead(void)
{
    const char *path = tmp_path("uneven.csv");
    const long rows = 200000;
    for (int long_first = 0; long_first <= 1; ++long_first)
    {
        write_uneven(path, long_first, rows);
        aenl_table_t t;
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &t, &g_err), g_err.msg);
        TEST_ASSERT_EQUAL_size_t((size_t)rows, t.n_rows);
        TEST_ASSERT_EQUAL_size_t(3u, t.n_cols);
        size_t bad = 0;
        for (long k = 0; k < rows; ++k)
        {
            const double want[3] = {(double)k, 1e-3 * (double)k, -(double)k / 7.0};
            for (size_t c = 0; c < 3; ++c)
            {
                bad += bits_of(aenl_table_col(&t, c)[k]) != bits_of(want[c]) ? 1u : 0u;
            }
        }
        TEST_ASSERT_EQUAL_size_t(0u, bad);
        TEST_ASSERT_EQUAL_size_t(0u, t.n_nan[0] + t.n_nan[1] + t.n_nan[2]);
        aenl_table_free(&t);
    }
    /* a header and 20 000 comment lines: more than the first block, and no data row */
    FILE *fp = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL(fp);
    (void)fputs("t,a,b\n", fp);
    for (int k = 0; k < 20000; ++k)
    {
        (void)fputs(k % 2 == 0 ? "# a comment\n" : "   \n", fp);
    }
    TEST_ASSERT_EQUAL_INT(0, fclose(fp));
    aenl_table_t t;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(path, &t, &g_err), g_err.msg);
    TEST_ASSERT_EQUAL_size_t(0u, t.n_rows);
    TEST_ASSERT_EQUAL_size_t(3u, t.n_cols);
    TEST_ASSERT_NULL(t.data);
    aenl_table_free(&t);
    (void)remove(path);
}

/* The decimals of a double printed to round trip (%.17g, as the project's own CSV writer does,
 * and %.16g to %.19g), 10^6 of them over 10^-30 .. 10^30, against strtod bit for bit; integers
 * that lie exactly halfway between two doubles (2^54 .. 2^63 plus half a step), which strtod
 * rounds to even; and 19 digits of points halfway between two doubles. */
static void test_parse_decimal_long_decimals(void)
{
    uint64_t rs = 1234u;
    size_t taken = 0;
    char buf[64];
    for (int i = 0; i < 1000000; ++i)
    {
        const double x = (test_uniform(&rs) < 0.5 ? -1.0 : 1.0) * (1.0 + test_uniform(&rs)) *
                         pow(10.0, (double)((int)(61.0 * test_uniform(&rs)) - 30));
        (void)snprintf(buf, sizeof(buf), "%.*g", 16 + (int)(4.0 * test_uniform(&rs)), x);
        double fast = 0.0;
        const double ref = strtod(buf, NULL);
        if (aenl_parse_decimal(buf, &fast))
        {
            ++taken;
            TEST_ASSERT_TRUE_MESSAGE(bits_of(fast) == bits_of(ref), buf);
        }
    }
    size_t halfway_taken = 0;
    for (int i = 0; i < 100000; ++i)
    {
        const int b = 54 + (int)(10.0 * test_uniform(&rs)); /* 2^b <= n < 2^(b+1) */
        const uint64_t step = (uint64_t)1 << (unsigned)(b - 52);
        uint64_t n = ((uint64_t)1 << (unsigned)b) +
                     step * (uint64_t)(test_uniform(&rs) * (double)((uint64_t)1 << 52u));
        n += step / 2u; /* halfway between two doubles */
        (void)snprintf(buf, sizeof(buf), "%llu", (unsigned long long)n);
        double fast = 0.0;
        if (aenl_parse_decimal(buf, &fast))
        {
            ++halfway_taken;
            TEST_ASSERT_TRUE_MESSAGE(bits_of(fast) == bits_of(strtod(buf, NULL)), buf);
        }
    }
    printf("long decimals: %zu of 10^6 taken by the fast path, %zu of 10^5 halfway integers\n",
           taken, halfway_taken);
    TEST_ASSERT_EQUAL_size_t(0, halfway_taken);
    /* 19 digits of a point halfway between two doubles (10^-5 .. 10^5): the decimal lies a
     * little above or below it, and a value rounded twice would go to the even neighbour */
    for (int i = 0; i < 200000; ++i)
    {
        const double d =
            (1.0 + test_uniform(&rs)) * pow(10.0, (double)((int)(11.0 * test_uniform(&rs)) - 5));
        const long double h = 0.5L * ((long double)d + (long double)nextafter(d, 2.0 * d));
        (void)snprintf(buf, sizeof(buf), "%.18Le", h);
        double fast = 0.0;
        if (aenl_parse_decimal(buf, &fast))
        {
            TEST_ASSERT_TRUE_MESSAGE(bits_of(fast) == bits_of(strtod(buf, NULL)), buf);
        }
    }
}

/* The fast decimal path against strtod (the reference): every string it takes converts to
 * strtod's value bit for bit, over random decimals of 1 to 20 digits with the point anywhere,
 * leading zeros, signs and exponents from -40 to 40 (some taken, some left to strtod); and the
 * forms it must leave to strtod are left. */
static void test_parse_decimal_matches_strtod(void)
{
    uint64_t rs = 77u;
    size_t taken = 0, left = 0;
    char buf[64];
    for (int i = 0; i < 200000; ++i)
    {
        size_t k = 0;
        if (test_uniform(&rs) < 0.3)
        {
            buf[k++] = test_uniform(&rs) < 0.5 ? '-' : '+';
        }
        const int nd = 1 + (int)(20.0 * test_uniform(&rs));
        const int point = (int)((double)(nd + 1) * test_uniform(&rs)); /* nd: no point */
        const int zeros = test_uniform(&rs) < 0.2 ? (int)(4.0 * test_uniform(&rs)) : 0;
        for (int z = 0; z < zeros; ++z)
        {
            buf[k++] = '0';
        }
        for (int d = 0; d < nd; ++d)
        {
            if (d == point)
            {
                buf[k++] = '.';
            }
            buf[k++] = (char)('0' + (int)(10.0 * test_uniform(&rs)));
        }
        if (test_uniform(&rs) < 0.4)
        {
            k += (size_t)snprintf(buf + k, sizeof(buf) - k, "%s%d",
                                  test_uniform(&rs) < 0.5 ? "e" : "E",
                                  (int)(81.0 * test_uniform(&rs)) - 40);
        }
        buf[k] = '\0';
        double fast = 0.0;
        char *end = NULL;
        const double ref = strtod(buf, &end);
        if (aenl_parse_decimal(buf, &fast))
        {
            ++taken;
            TEST_ASSERT_TRUE_MESSAGE(*end == '\0' && bits_of(fast) == bits_of(ref), buf);
        }
        else
        {
            ++left;
        }
    }
    printf("fast decimal path: %zu of %zu random decimals taken, the rest left to strtod\n", taken,
           taken + left);
    TEST_ASSERT_TRUE(taken > 50000u && left > 20000u);
    /* exact cases and signed zeros */
    const char *const same[] = {"0",
                                "-0",
                                "-0.000",
                                "+0e5",
                                "1",
                                ".5",
                                "5.",
                                "0.1",
                                "-2.5e-3",
                                "1e22",
                                "1E-22",
                                "123456789012345",
                                "9007199254740992",
                                "0.006451612903",
                                "4.5e+01",
                                "000123.4500"};
    for (size_t i = 0; i < sizeof(same) / sizeof(same[0]); ++i)
    {
        double fast = 1.0;
        TEST_ASSERT_TRUE_MESSAGE(aenl_parse_decimal(same[i], &fast), same[i]);
        TEST_ASSERT_TRUE_MESSAGE(bits_of(fast) == bits_of(strtod(same[i], NULL)), same[i]);
    }
    /* not plain decimals, or beyond the exact range: left to strtod, *v untouched */
    const char *const others[] = {"",      ".",       "-",
                                  "1e",    "1e+",     "1.2.3",
                                  "0x1p3", "inf",     "nan",
                                  "1e28",  "1e-28",   "9007199254740993",
                                  "1,5",   "1e00001", "12345678901234567890",
                                  "1 ",    "--1"};
    for (size_t i = 0; i < sizeof(others) / sizeof(others[0]); ++i)
    {
        double v = 42.0;
        TEST_ASSERT_FALSE_MESSAGE(aenl_parse_decimal(others[i], &v), others[i]);
        TEST_ASSERT_EQUAL_DOUBLE(42.0, v);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_err_keeps_first_cause);
    RUN_TEST(test_share_path_order_and_error);
    RUN_TEST(test_csv_time_names);
    RUN_TEST(test_csv_control_byte_any_position);
    RUN_TEST(test_parse_decimal_matches_strtod);
    RUN_TEST(test_parse_decimal_long_decimals);
    RUN_TEST(test_time_steps);
    RUN_TEST(test_time_steps_against_definition);
    RUN_TEST(test_time_steps_decade_edges);
    RUN_TEST(test_table_read_sized_ahead);
    RUN_TEST(test_table_round_trip_is_bit_exact);
    RUN_TEST(test_csv_writer_streams_rows);
    RUN_TEST(test_csv_writer_rejects_bad_names_and_inf);
    RUN_TEST(test_csv_reads_crlf);
    RUN_TEST(test_csv_reads_semicolons_and_tabs);
    RUN_TEST(test_csv_strips_bom_and_trims_names);
    RUN_TEST(test_csv_missing_cells_are_nan_and_counted);
    RUN_TEST(test_csv_header_only_gives_zero_rows);
    RUN_TEST(test_csv_skips_comments_and_blank_lines_counting_them);
    RUN_TEST(test_csv_long_lines);
    RUN_TEST(test_csv_error_not_a_number);
    RUN_TEST(test_csv_error_unit_row);
    RUN_TEST(test_csv_error_trailing_garbage);
    RUN_TEST(test_csv_error_inf);
    RUN_TEST(test_csv_error_ragged_rows);
    RUN_TEST(test_csv_error_bad_header);
    RUN_TEST(test_csv_error_empty_file);
    RUN_TEST(test_csv_error_binary_line);
    RUN_TEST(test_csv_error_missing_file);
    RUN_TEST(test_csv_streams_a_million_rows);
    RUN_TEST(test_outfile_not_visible_before_commit);
    RUN_TEST(test_outfile_abort_leaves_no_file);
    RUN_TEST(test_outfile_existing_file_kept_until_commit);
    RUN_TEST(test_outfile_missing_folder_fails_cleanly);
    RUN_TEST(test_outfile_run_failure_restores_files);
    RUN_TEST(test_outfile_run_refuses_inputs_and_repeats);
    RUN_TEST(test_figure_cut_short_is_incomplete);
    RUN_TEST(test_outfile_commit_failure_removes_temporary);
    RUN_TEST(test_outfile_abort_all_removes_pending);
    RUN_TEST(test_outfile_device_written_not_replaced);
    RUN_TEST(test_outfile_fifo_written_not_replaced);
    RUN_TEST(test_outfile_symlink_written_through);
    RUN_TEST(test_outfile_unwritable_fails_cleanly);
    return UNITY_END();
}
