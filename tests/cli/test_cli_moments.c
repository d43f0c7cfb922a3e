/* SPDX-License-Identifier: MIT */
/**
 * @file test_cli_moments.c
 * @brief `aenl moments` end to end: the CSV it writes agrees with a direct evaluation of the
 *        paper's formula, and every kind of bad input gives exit 2, one message on stderr naming
 *        what and where, nothing on stdout and no output file.
 */
#include "aenl_cli_test.h"

#include <math.h>

#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* A sampled decaying oscillation with a little deterministic jitter. */
static const char *write_signal(const char *name, size_t n, int with_nan)
{
    static char text[1 << 20];
    size_t pos = (size_t)snprintf(text, sizeof(text), "t,alpha,xi\n");
    for (size_t i = 0; i < n && pos + 128 < sizeof(text); ++i)
    {
        const double t = 0.01 * (double)i;
        const double a = exp(-0.05 * t) * sin(6.0 * t) + 0.05 * sin(37.0 * t + 1.0);
        if (with_nan && i % 97 == 5)
        {
            pos += (size_t)snprintf(text + pos, sizeof(text) - pos, "%.4f,nan,%.6f\n", t, 0.5 * a);
        }
        else
        {
            pos +=
                (size_t)snprintf(text + pos, sizeof(text) - pos, "%.4f,%.9f,%.6f\n", t, a, 0.5 * a);
        }
    }
    return cli_file(name, text);
}

static void test_cli_moments_csv_matches_direct_formula(void)
{
    const char *data = write_signal("sig.csv", 3000, 0);
    const char *args[] = {"moments", data,         "--channel",   "alpha",       "--lags",
                          "1,5",     "--grid",     "-0.5:0.5:11", "--bandwidth", "0.2",
                          "-o",      "out_ok.csv", NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    char path[600];
    (void)snprintf(path, sizeof(path), "%s/out_ok.csv", AENL_TEST_TMP_DIR);
    FILE *f = fopen(path, "r");
    TEST_ASSERT_NOT_NULL(f);
    /* Re-read the input and evaluate formula (10) directly at each output row. */
    static double x[3000];
    FILE *in = fopen(data, "r");
    TEST_ASSERT_NOT_NULL(in);
    char line[256];
    TEST_ASSERT_NOT_NULL(fgets(line, sizeof(line), in));
    for (size_t i = 0; i < 3000; ++i)
    {
        double t, xi;
        /* NOLINTNEXTLINE(cert-err34-c): a known file; the field count is asserted */
        TEST_ASSERT_EQUAL_INT(3, fscanf(in, "%lf,%lf,%lf", &t, &x[i], &xi));
    }
    (void)fclose(in);
    int rows = 0;
    while (fgets(line, sizeof(line), f) != NULL)
    {
        unsigned lag;
        double node, mean, var, neff, se;
        if (line[0] == '#' ||
            /* NOLINTNEXTLINE(cert-err34-c): the field count is checked */
            sscanf(line, "%u,%lf,%lf,%lf,%lf,%lf", &lag, &node, &mean, &var, &neff, &se) != 6)
        {
            continue;
        }
        double sw = 0, s1 = 0, s2 = 0;
        /* Every lag is conditioned on the same samples c = 1 .. N-1-max_lag (the split needs
         * c >= 1; the largest lag here is 5). */
        for (size_t i = lag; i < 3000; ++i)
        {
            const size_t c = i - lag;
            const double d = fabs(x[c] - node);
            if (d < 0.2 && c >= 1u && c + 5u <= 2999u)
            {
                const double w = (1.0 - d / 0.2) / 0.2;
                sw += w;
                s1 += w * x[i];
                s2 += w * x[i] * x[i];
            }
        }
        TEST_ASSERT_TRUE(sw > 0.0);
        const double m = s1 / sw;
        TEST_ASSERT_DOUBLE_WITHIN(1e-9, m, mean);
        TEST_ASSERT_DOUBLE_WITHIN(1e-9, s2 / sw - m * m, var);
        rows++;
    }
    (void)fclose(f);
    TEST_ASSERT_EQUAL_INT(22, rows);
    /* The summary on stdout names the bandwidth and how it was chosen. */
    TEST_ASSERT_NOT_NULL(strstr(r.out, "bandwidth 0.2 (given)"));
}

static void test_cli_moments_reports_cv_bandwidth(void)
{
    const char *data = write_signal("sig_cv.csv", 4000, 1);
    const char *args[] = {"moments", data, "--channel", "alpha", NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_NOT_NULL(strstr(r.out, "# bandwidth="));
    TEST_ASSERT_NOT_NULL(strstr(r.out, "method=cv"));
    TEST_ASSERT_NOT_NULL(strstr(r.out, "missing=42"));
    TEST_ASSERT_NOT_NULL(strstr(r.out, "lag,x,mean,var,n_eff,se\n"));
}

/* A clean sinusoid with an incommensurate period of 97.3 samples: with the automatic pre-filter
 * and lags, the expansion must find the period and the analytic restoring force a = -w^2 p. */
static void test_cli_moments_expansion_of_a_sinusoid(void)
{
    static char text[1 << 20];
    const double w = 2.0 * 3.14159265358979323846 / 97.3;
    size_t pos = (size_t)snprintf(text, sizeof(text), "t,alpha\n");
    for (int i = 0; i < 8000 && pos + 64 < sizeof(text); ++i)
    {
        pos += (size_t)snprintf(text + pos, sizeof(text) - pos, "%d,%.12f\n", i, sin(w * i));
    }
    const char *data = cli_file("sine.csv", text);
    const char *args[] = {"moments", data,         "--prefilter", "auto",        "--lags",
                          "auto",    "--grid",     "-1:1:21",     "--bandwidth", "0.15",
                          "-o",      "sine_m.csv", "--expansion", "sine_x.csv",  NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "period 97."), r.out);
    char path[600];
    (void)snprintf(path, sizeof(path), "%s/sine_x.csv", AENL_TEST_TMP_DIR);
    FILE *f = fopen(path, "r");
    TEST_ASSERT_NOT_NULL(f);
    char line[512];
    int n_checked = 0;
    while (fgets(line, sizeof(line), f) != NULL)
    {
        int dir;
        double x, p, v, a;
        /* NOLINTNEXTLINE(cert-err34-c): the field count is checked */
        if (line[0] == '#' || sscanf(line, "%d,%lf,%lf,%lf,%lf", &dir, &x, &p, &v, &a) != 5 ||
            fabs(x) > 0.7)
        {
            continue;
        }
        TEST_ASSERT_DOUBLE_WITHIN(0.02 * w * w, -w * w * p, a);
        if (dir == 1)
        {
            TEST_ASSERT_DOUBLE_WITHIN(0.03 * w, w * sqrt(1.0 - p * p), v);
        }
        n_checked++;
    }
    (void)fclose(f);
    TEST_ASSERT_GREATER_THAN_INT(30, n_checked);
}

/* Bad input: exit 2, one line on stderr containing `needle`, nothing on stdout, no output. */
static void expect_rejected(const char *const *args, const char *needle)
{
    TEST_ASSERT_NOT_NULL(needle);
    cli_expect_refused(args, needle);
    TEST_ASSERT_TRUE_MESSAGE(cli_no_file_like("bad_out"), "an output file was left behind");
}

static void test_cli_moments_rejects_bad_input(void)
{
    const char *good = write_signal("good.csv", 600, 0);
    const char *nan_only = cli_file("allnan.csv", "t,alpha\n0,nan\n1,nan\n2,\n3,NaN\n");
    const char *constant = cli_file("const.csv", "t,alpha\n0,1.5\n1,1.5\n2,1.5\n3,1.5\n4,1.5\n"
                                                 "5,1.5\n6,1.5\n7,1.5\n8,1.5\n9,1.5\n10,1.5\n");
    const char *garbage = cli_file("garbage.csv", "t,alpha\n0,1\n1,abc\n");
    const char *ragged = cli_file("ragged.csv", "t,alpha\n0,1\n1\n");
    const char *header_only = cli_file("header.csv", "t,alpha\n");
    const char *empty = cli_file("empty.csv", "");

    const char *a1[] = {"moments", "/nonexistent/x.csv", "--channel", "alpha",
                        "-o",      "bad_out.csv",        NULL};
    expect_rejected(a1, "/nonexistent/x.csv");
    const char *a2[] = {"moments", good, "--channel", "beta", "-o", "bad_out.csv", NULL};
    expect_rejected(a2, "no channel 'beta'");
    const char *a3[] = {"moments", nan_only, "--channel", "alpha", "-o", "bad_out.csv", NULL};
    expect_rejected(a3, "no finite sample");
    const char *a4[] = {"moments", constant, "-o", "bad_out.csv", NULL};
    expect_rejected(a4, "constant signal");
    const char *a5[] = {"moments", good, "--channel",   "alpha", "--grid",
                        "-1:1:2",  "-o", "bad_out.csv", NULL};
    expect_rejected(a5, "--grid N");
    const char *a6[] = {"moments", good, "--channel",   "alpha", "--bandwidth",
                        "-0.1",    "-o", "bad_out.csv", NULL};
    expect_rejected(a6, "--bandwidth");
    const char *a7[] = {"moments", good, "--channel",   "alpha", "--lags",
                        "1,99999", "-o", "bad_out.csv", NULL};
    expect_rejected(a7, "compile-time maximum");
    const char *a8[] = {"moments", garbage, "--channel", "alpha", "-o", "bad_out.csv", NULL};
    expect_rejected(a8, "garbage.csv:3:2");
    const char *a9[] = {"moments", ragged, "--channel", "alpha", "-o", "bad_out.csv", NULL};
    expect_rejected(a9, "ragged.csv:3");
    const char *a10[] = {"moments", header_only, "--channel", "alpha", "-o", "bad_out.csv", NULL};
    expect_rejected(a10, "no data rows");
    const char *a11[] = {"moments", empty, "-o", "bad_out.csv", NULL};
    expect_rejected(a11, "empty");
    const char *a12[] = {"moments", good, "--channel", "alpha", "--bogus", NULL};
    expect_rejected(a12, "unknown option --bogus");
    const char *a13[] = {"moments", NULL};
    expect_rejected(a13, "no data file");
    const char *a14[] = {"moments", good, "-o", "bad_out.csv", NULL};
    expect_rejected(a14, "--channel");
    const char *a15[] = {
        "moments", good, "--channel", "alpha", "-o", "/nonexistent/dir/bad_out.csv", NULL};
    expect_rejected(a15, "/nonexistent/dir");
    const char *a16[] = {"moments", good, "--channel", "alpha", "--lags", "0", NULL};
    expect_rejected(a16, "--lags");
    const char *a17[] = {"moments", good, "--channel", "alpha", "--grid", "1:-1:10", NULL};
    expect_rejected(a17, "--grid");
    const char *a18[] = {"moments", good, "--channel", "alpha", "--bandwidth", "nan", NULL};
    expect_rejected(a18, "--bandwidth");
    const char *a19[] = {"moments", good, "--channel", "alpha", "--prefilter", "0.7", NULL};
    expect_rejected(a19, "--prefilter");
    const char *a20[] = {"moments", good,          "--channel",     "alpha", "--lags",
                         "1,5",     "--expansion", "bad_out_x.csv", NULL};
    expect_rejected(a20, "at least 3 lags");
    const char *ramp = cli_file("ramp.csv", "t,alpha\n0,0\n1,1\n2,2\n3,3\n4,4\n5,5\n6,6\n7,7\n"
                                            "8,8\n9,9\n10,10\n11,11\n12,12\n13,13\n14,14\n");
    const char *a21[] = {"moments", ramp, "--lags", "auto", "-o", "bad_out.csv", NULL};
    expect_rejected(a21, "fewer than two full oscillations");
}

/* A time column under a name of its own: --time names it; without it, the column is a channel
 * and a note on stderr says so. */
static void test_cli_time_column_named_by_option(void)
{
    static char text[1 << 20];
    size_t pos = (size_t)snprintf(text, sizeof(text), "elapsed,alpha,xi\n");
    for (size_t i = 0; i < 3000 && pos + 128 < sizeof(text); ++i)
    {
        const double t = 0.01 * (double)i;
        const double a = exp(-0.05 * t) * sin(6.0 * t) + 0.05 * sin(37.0 * t + 1.0);
        pos += (size_t)snprintf(text + pos, sizeof(text) - pos, "%.4f,%.9f,%.6f\n", t, a,
                                0.5 * a + 0.01 * cos(11.0 * t));
    }
    const char *data = cli_file("elapsed.csv", text);
    cli_result_t r;
    const char *named[] = {"identify", data, "--method", "test", "--time", "elapsed", NULL};
    cli_run(&r, named);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.err_lines, r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "3000 samples, 2 channels"), r.out);
    TEST_ASSERT_NULL(strstr(r.out, "\nelapsed "));
    const char *unnamed[] = {"identify", data, "--method", "test", NULL};
    cli_run(&r, unnamed);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "3000 samples, 3 channels"), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, "has no time column"), r.err);
    const char *json[] = {"identify", data, "--method", "test", "--json", NULL};
    cli_run(&r, json); /* a JSON output keeps stderr quiet */
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.err_lines, r.err);
    const char *mom[] = {"moments", data,      "--channel", "alpha",           "--bandwidth", "0.2",
                         "--time",  "elapsed", "-o",        "out_elapsed.csv", NULL};
    cli_run(&r, mom);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.err_lines, r.err);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_cli_moments_csv_matches_direct_formula);
    RUN_TEST(test_cli_moments_reports_cv_bandwidth);
    RUN_TEST(test_cli_moments_expansion_of_a_sinusoid);
    RUN_TEST(test_cli_moments_rejects_bad_input);
    RUN_TEST(test_cli_time_column_named_by_option);
    return UNITY_END();
}
