/* SPDX-License-Identifier: MIT */
/**
 * @file test_cli_fit.c
 * @brief `aenl fit` end to end on a record simulated here from a known 3-mode switching model:
 *        the JSON has the modes in threshold order with A, b, Q, interval, eig, frequency (in
 *        cycles per unit of the t column) and damping close to the truth, a non-decreasing
 *        loglik; the model INI and the C header are written, and the header compiles against the
 *        core as float and double (and with arm-none-eabi-gcc for the Cortex-M4F when present).
 *        Bad input: exit 2, one message on stderr, nothing on stdout, no output file.
 */
#include "aenl_cli_test.h"
#include "aenl_test_rand.h"
#include "aenl_tools/aenl_io.h" /* AENL_PRINTF_LIKE */

#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>

#include "unity.h"

#define PI 3.14159265358979323846
#define DT 0.5

void setUp(void)
{
}

void tearDown(void)
{
}

/* snprintf into out[cap]; the test fails if the text (a path or a command) does not fit. */
static void fmt(char *out, size_t cap, const char *f, ...) AENL_PRINTF_LIKE(3, 4);
static void fmt(char *out, size_t cap, const char *f, ...)
{
    va_list ap;
    va_start(ap, f);
    const int len = vsnprintf(out, cap, f, ap);
    va_end(ap);
    TEST_ASSERT_TRUE_MESSAGE(len >= 0 && (size_t)len < cap, "path or command too long");
}
static uint64_t g_lcg = 77u;

/* Outer modes: oscillator 1 at 0.30 rad/sample, inner mode at 0.18; oscillator 2 at 0.55. */
static const double k_th1[3] = {0.30, 0.18, 0.30};

static const char *write_record(const char *name, size_t n)
{
    static char text[4 << 20];
    size_t pos = (size_t)snprintf(text, sizeof(text), "t,alpha,xi\n");
    double x[4] = {0.5, 0.0, 0.1, 0.0};
    for (size_t k = 0; k < n && pos + 128 < sizeof(text); ++k)
    {
        pos += (size_t)snprintf(text + pos, sizeof(text) - pos, "%.3f,%.9f,%.9f\n", DT * (double)k,
                                x[0] + 0.03 * test_gauss(&g_lcg), x[2] + 0.02 * test_gauss(&g_lcg));
        const int s = x[0] < -0.2 ? 0 : (x[0] < 0.2 ? 1 : 2);
        const double c1 = (s == 1 ? 0.99 : 0.985) * cos(k_th1[s]);
        const double s1 = (s == 1 ? 0.99 : 0.985) * sin(k_th1[s]);
        const double c2 = 0.97 * cos(0.55), s2 = 0.97 * sin(0.55);
        const double off = (s == 0) ? -0.2 : (s == 2 ? 0.2 : 0.0);
        const double d0 = x[0] - off;
        double xn[4];
        xn[0] = off + c1 * d0 - s1 * x[1] + 0.03 * x[2] + 0.05 * test_gauss(&g_lcg);
        xn[1] = s1 * d0 + c1 * x[1] + 0.05 * test_gauss(&g_lcg);
        xn[2] = 0.05 * x[0] + c2 * x[2] - s2 * x[3] + 0.05 * test_gauss(&g_lcg);
        xn[3] = s2 * x[2] + c2 * x[3] + 0.05 * test_gauss(&g_lcg);
        memcpy(x, xn, sizeof(x));
    }
    return cli_file(name, text);
}

static double true_freq(double th)
{
    return th / (2.0 * PI * DT);
}

static void test_cli_fit_json_model_and_header(void)
{
    const char *data = write_record("fit_sig.csv", 20000);
    const char *args[] = {"fit",    data, "--thresholds",  "alpha:-0.2,0.2", "--states",    "4",
                          "--json", "-o", "fit_model.ini", "--c-header",     "fit_model.h", NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    cJSON *root = cJSON_Parse(r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, "stdout is not JSON");
    cJSON *modes = cJSON_GetObjectItem(root, "modes");
    TEST_ASSERT_EQUAL_INT(3, cJSON_GetArraySize(modes));
    for (int s = 0; s < 3; ++s)
    {
        cJSON *m = cJSON_GetArrayItem(modes, s);
        cJSON *iv = cJSON_GetObjectItem(m, "interval");
        TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(iv));
        if (s == 0)
        {
            TEST_ASSERT_TRUE(cJSON_IsNull(cJSON_GetArrayItem(iv, 0)));
            TEST_ASSERT_DOUBLE_WITHIN(1e-12, -0.2, cJSON_GetArrayItem(iv, 1)->valuedouble);
        }
        if (s == 1)
        {
            TEST_ASSERT_DOUBLE_WITHIN(1e-12, -0.2, cJSON_GetArrayItem(iv, 0)->valuedouble);
            TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.2, cJSON_GetArrayItem(iv, 1)->valuedouble);
        }
        TEST_ASSERT_EQUAL_INT(4, cJSON_GetArraySize(cJSON_GetObjectItem(m, "A")));
        TEST_ASSERT_EQUAL_INT(4, cJSON_GetArraySize(cJSON_GetObjectItem(m, "b")));
        TEST_ASSERT_EQUAL_INT(4, cJSON_GetArraySize(cJSON_GetObjectItem(m, "Q")));
        TEST_ASSERT_EQUAL_INT(4, cJSON_GetArraySize(cJSON_GetObjectItem(m, "eig")));
        cJSON *fr = cJSON_GetObjectItem(m, "frequency");
        cJSON *dz = cJSON_GetObjectItem(m, "damping");
        TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(fr));
        TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(dz));
        /* sorted by frequency: oscillator 1 (slower) first; in cycles per unit of t */
        const double f0 = cJSON_GetArrayItem(fr, 0)->valuedouble;
        const double f1 = cJSON_GetArrayItem(fr, 1)->valuedouble;
        TEST_ASSERT_DOUBLE_WITHIN(0.04 * true_freq(k_th1[s]), true_freq(k_th1[s]), f0);
        TEST_ASSERT_DOUBLE_WITHIN(0.04 * true_freq(0.55), true_freq(0.55), f1);
        const double z1 = cJSON_GetArrayItem(dz, 1)->valuedouble;
        const double s_re = log(0.97), z1_true = -s_re / sqrt(s_re * s_re + 0.55 * 0.55);
        TEST_ASSERT_DOUBLE_WITHIN(0.07, z1_true, z1);
    }
    TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(cJSON_GetObjectItem(root, "C")));
    TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(cJSON_GetObjectItem(root, "R")));
    cJSON *ll = cJSON_GetObjectItem(root, "loglik");
    TEST_ASSERT_EQUAL_INT(50, cJSON_GetArraySize(ll));
    for (int i = 1; i < cJSON_GetArraySize(ll); ++i)
    {
        const double a = cJSON_GetArrayItem(ll, i - 1)->valuedouble;
        const double b = cJSON_GetArrayItem(ll, i)->valuedouble;
        TEST_ASSERT_TRUE_MESSAGE(b >= a - 1e-9 * fabs(a), "loglik decreased");
    }
    cJSON_Delete(root);

    /* the INI and the header exist; the header compiles against the core, f32 and f64 */
    char ini[600], hdr[600], src[600], cmd[4096];
    fmt(ini, sizeof(ini), "%s/fit_model.ini", AENL_TEST_TMP_DIR);
    fmt(hdr, sizeof(hdr), "%s/fit_model.h", AENL_TEST_TMP_DIR);
    TEST_ASSERT_TRUE(cli_exists(ini));
    TEST_ASSERT_TRUE(cli_exists(hdr));
    fmt(src, sizeof(src), "%s", AENL_SOURCE_DIR);
    cli_file("use_model.c", "#include \"aenl/aenl_skf.h\"\n#include \"fit_model.h\"\n"
                            "int use_model(void);\n"
                            "int use_model(void)\n{\n    static aenl_skf_t f;\n"
                            "    return (int)aenl_skf_init(&f, &fit_model);\n}\n");
    const char *flags = "-std=c99 -Wall -Wextra -Wpedantic -Wconversion -Wdouble-promotion "
                        "-Wfloat-equal -Werror -c";
    for (int dbl = 0; dbl < 2; ++dbl)
    {
        fmt(cmd, sizeof(cmd),
            "cc %s -DAENL_USE_DOUBLE=%d -I'%s/include' -I'%s' '%s/use_model.c' "
            "-o '%s/use_model.o'",
            flags, dbl, src, AENL_TEST_TMP_DIR, AENL_TEST_TMP_DIR, AENL_TEST_TMP_DIR);
        /* NOLINTNEXTLINE(cert-env33-c): test, fixed command from build-time paths */
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, system(cmd), cmd);
    }
    if (system("command -v arm-none-eabi-gcc >/dev/null 2>&1") == 0) /* NOLINT(cert-env33-c) */
    {
        fmt(cmd, sizeof(cmd),
            "arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -Os "
            "%s -I'%s/include' -I'%s' '%s/use_model.c' -o '%s/use_model_m4f.o'",
            flags, src, AENL_TEST_TMP_DIR, AENL_TEST_TMP_DIR, AENL_TEST_TMP_DIR);
        /* NOLINTNEXTLINE(cert-env33-c): test, fixed command from build-time paths */
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, system(cmd), cmd);
    }
    /* a capacity check: the header refuses a core built with too few states */
    fmt(cmd, sizeof(cmd),
        "cc %s -DAENL_SKF_MAX_X=3 -I'%s/include' -I'%s' '%s/use_model.c' "
        "-o '%s/use_model.o' 2>/dev/null",
        flags, src, AENL_TEST_TMP_DIR, AENL_TEST_TMP_DIR, AENL_TEST_TMP_DIR);
    TEST_ASSERT_TRUE(system(cmd) != 0); /* NOLINT(cert-env33-c): test, fixed command */
}

static void expect_usage_error(const char *const *args, const char *what)
{
    cli_expect_refused(args, NULL);
    TEST_ASSERT_TRUE_MESSAGE(cli_no_file_like("bad_out"), what);
}

static void test_cli_fit_bad_input(void)
{
    const char *data = write_record("fit_small.csv", 3000);
    const char *a1[] = {"fit", data, "-o", "bad_out.ini", NULL};
    expect_usage_error(a1, "no thresholds");
    const char *a2[] = {"fit", data, "--thresholds", "beta:0.1", "-o", "bad_out.ini", NULL};
    expect_usage_error(a2, "unknown channel");
    const char *a3[] = {"fit", data, "--thresholds", "alpha:0.2,-0.2", "-o", "bad_out.ini", NULL};
    expect_usage_error(a3, "descending thresholds");
    const char *a4[] = {"fit", data, "--thresholds", "alpha:9", "-o", "bad_out.ini", NULL};
    expect_usage_error(a4, "empty mode");
    const char *a5[] = {"fit", data, "--thresholds", "alpha:0", "--freeze", "A,Z", NULL};
    expect_usage_error(a5, "bad freeze name");
    const char *bad_t = cli_file("fit_badt.csv", "t,alpha,xi\n0,1,2\n1,1,2\n3,1,2\n4,1,2\n");
    const char *a6[] = {"fit", bad_t, "--thresholds", "alpha:0", "-o", "bad_out.ini", NULL};
    expect_usage_error(a6, "non-uniform time");
    const char *a7[] = {"fit",    data,   "--thresholds", "alpha:0",     "--c-header", "bad_out.h",
                        "--name", "9bad", "-o",           "bad_out.ini", NULL};
    expect_usage_error(a7, "bad identifier");
    const char *a8[] = {"fit",    data, "--thresholds", "alpha:0",     "--c-header", "bad_out.h",
                        "--name", "",   "-o",           "bad_out.ini", NULL};
    expect_usage_error(a8, "empty model name");
    const char *a9[] = {"fit", data, "--thresholds", "alpha:0", "--init", "n4sid", NULL};
    expect_usage_error(a9, "unknown start");
}

/* The other start and plain EM are reachable from the command line; the log still rises. */
static void test_cli_fit_subspace_start_and_plain_em(void)
{
    const char *data = write_record("fit_small2.csv", 3000);
    const char *args[] = {
        "fit",    data,       "--thresholds", "alpha:-0.2,0.2", "--states", "4",
        "--init", "subspace", "--plain-em",   "--iter",         "8",        "--json",
        NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    cJSON *root = cJSON_Parse(r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, "stdout is not JSON");
    cJSON *ll = cJSON_GetObjectItem(root, "loglik");
    TEST_ASSERT_EQUAL_INT(8, cJSON_GetArraySize(ll));
    for (int i = 1; i < cJSON_GetArraySize(ll); ++i)
    {
        TEST_ASSERT_TRUE(cJSON_GetArrayItem(ll, i)->valuedouble >=
                         cJSON_GetArrayItem(ll, i - 1)->valuedouble -
                             1e-9 * fabs(cJSON_GetArrayItem(ll, i - 1)->valuedouble));
    }
    cJSON_Delete(root);
}

/* --bootstrap: standard errors in the table, and a progress bar on a terminal only (stderr
 * quiet through a pipe; on a pseudo-terminal from script(1), a bar that is erased at the end). */
static void test_cli_fit_bootstrap_and_its_progress_bar(void)
{
    const char *data = write_record("fit_boot.csv", 3000);
    const char *args[] = {"fit", data, "--thresholds", "alpha:0.0", "--iter", "5", "--bootstrap",
                          "3",   NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.err_lines, r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "parametric bootstrap: "), r.out);
    /* NOLINTNEXTLINE(cert-env33-c): test helper, fixed command */
    if (system("script -qec true /dev/null > /dev/null 2>&1") != 0)
    {
        TEST_IGNORE_MESSAGE("script(1) cannot open a pseudo-terminal here: the bar is not drawn");
    }
    char cmd[2048];
    (void)snprintf(cmd, sizeof(cmd),
                   "script -qec \"'%s' fit '%s' --thresholds alpha:0.0 --iter 5 --bootstrap 3\" "
                   "/dev/null",
                   AENL_CLI_PATH, data);
    FILE *p = popen(cmd, "r"); /* NOLINT(cert-env33-c): test helper, fixed command */
    TEST_ASSERT_NOT_NULL(p);
    static char tty[1 << 16];
    const size_t got = fread(tty, 1, sizeof(tty) - 1u, p);
    tty[got] = '\0';
    TEST_ASSERT_EQUAL_INT(0, pclose(p));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(tty, "aenl fit: bootstrap [########################] 3/3"),
                                 tty);
    const char *erased = strstr(tty, "\r\033[K");
    TEST_ASSERT_NOT_NULL_MESSAGE(erased, tty);
    TEST_ASSERT_NOT_NULL(strstr(erased, "parametric bootstrap: ")); /* the output after it */
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_cli_fit_json_model_and_header);
    RUN_TEST(test_cli_fit_bad_input);
    RUN_TEST(test_cli_fit_subspace_start_and_plain_em);
    RUN_TEST(test_cli_fit_bootstrap_and_its_progress_bar);
    return UNITY_END();
}
