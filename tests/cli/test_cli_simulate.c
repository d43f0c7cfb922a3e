/* SPDX-License-Identifier: MIT */
/**
 * @file test_cli_simulate.c
 * @brief `aenl simulate` and `aenl flutter` end to end: the CSV contract (columns and units of
 *        docs/simulate.md), the same file for the same seed, the flutter speeds of the classic
 *        airfoil (U* 6.2851) and of Conner's section (23.897 m/s) through --json, and bad INIs:
 *        exit 2, one message naming file:line and key, nothing on stdout, no file.
 */
#define _DEFAULT_SOURCE /* mknod, makedev */

#include "aenl_cli_test.h"
#include "aenl_test_device.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>

#include "unity.h"

#define EXAMPLES AENL_SOURCE_DIR "/tools/examples/"
/* EXAMPLES "name.ini" in argument lists is a path, not a missing comma. */
/* NOLINTBEGIN(bugprone-suspicious-missing-comma) */

void setUp(void)
{
}

void tearDown(void)
{
}

static void test_cli_simulate_writes_the_csv_contract(void)
{
    const char *args[] = {"simulate", EXAMPLES "validate_linear_u4.ini", "-o", "sim_ok.csv", NULL};
    const char *args3[] = {"simulate", EXAMPLES "validate_conner_flap_u15.ini", NULL};
    static char text[1 << 16];
    char path[600];
    cli_result_t r;
    size_t n_lines = 0;
    const char *p;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
    (void)snprintf(path, sizeof(path), "%s/sim_ok.csv", AENL_TEST_TMP_DIR);
    cli_slurp(path, text, sizeof(text));
    TEST_ASSERT_EQUAL_INT(0, strncmp(text, "t,alpha,xi\n0,0.017453292519943", 30));
    for (p = text; *p; ++p)
    {
        n_lines += (*p == '\n');
    }
    TEST_ASSERT_EQUAL_size_t(602, n_lines); /* header + 601 samples (300 / 0.5 + 1) */
    /* section3dof to stdout */
    cli_run(&r, args3);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT(0, strncmp(r.out, "t,h,alpha,beta\n0,0,0.017453292519943", 36));
}

/* A forced excitation adds its force as the last column, noise-free and the same on stdout. */
static void test_cli_simulate_writes_the_force_column(void)
{
    const char *args[] = {"simulate", EXAMPLES "section3dof_multisine.ini", "-o", "sim_ms.csv",
                          NULL};
    const char *args_out[] = {"simulate", EXAMPLES "section3dof_multisine.ini", NULL};
    static char text[1 << 20];
    char path[600];
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    (void)snprintf(path, sizeof(path), "%s/sim_ms.csv", AENL_TEST_TMP_DIR);
    cli_slurp(path, text, sizeof(text));
    TEST_ASSERT_EQUAL_INT(0, strncmp(text, "t,h,alpha,beta,f_pitch\n", 23));
    cli_run(&r, args_out);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT(0, strncmp(r.out, text, 4000));

    /* The model-based test refuses a forced baseline rather than rebuild its force over the
     * record's length: the response columns (the force column cut off) against the same INI. */
    static char resp[1 << 20];
    size_t k = 0;
    for (const char *p = text; *p != '\0' && k + 2 < sizeof(resp);)
    {
        const char *eol = strchr(p, '\n');
        if (eol == NULL)
        {
            break;
        }
        const char *last = p;
        for (const char *q = p; q < eol; ++q)
        {
            last = *q == ',' ? q : last;
        }
        memcpy(resp + k, p, (size_t)(last - p));
        k += (size_t)(last - p);
        resp[k++] = '\n';
        p = eol + 1;
    }
    resp[k] = '\0';
    const char *rec = cli_file("sim_ms_response.csv", resp);
    const char *model_args[] = {"identify", rec, "--model", EXAMPLES "section3dof_multisine.ini",
                                NULL};
    cli_run(&r, model_args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, "forced excitation"), r.err);
}

/* Output targets that are not regular files are written, never replaced: "-" and /dev/stdout
 * give the CSV on standard output, /dev/stderr on standard error (through the process's own
 * stream, so an appending redirection keeps appending). */
static void test_cli_simulate_writes_to_stdout_and_devices(void)
{
    const char *dash[] = {"simulate", EXAMPLES "validate_linear_u4.ini", "-o", "-", NULL};
    const char *named[] = {"simulate", EXAMPLES "validate_linear_u4.ini", "-o", "/dev/stdout",
                           NULL};
    cli_result_t r;
    cli_run(&r, dash);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT(0, strncmp(r.out, "t,alpha,xi\n0,0.017453292519943", 30));
    cli_run(&r, named);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT(0, strncmp(r.out, "t,alpha,xi\n0,0.017453292519943", 30));
    const char *to_err[] = {"simulate", EXAMPLES "validate_linear_u4.ini", "-o", "/dev/stderr",
                            NULL};
    cli_run(&r, to_err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
    TEST_ASSERT_EQUAL_INT(0, strncmp(r.err, "t,alpha,xi\n0,0.017453292519943", 30));
}

/* A character device given to -o stays the device it is. As root a private twin of /dev/null
 * (1, 3) is made here, so a regression cannot replace the system's; where root may not make one
 * (or not open it: a nodev mount), the check is skipped rather than run on /dev/null itself.
 * Without root /dev/null is used, which a regression could not replace (its folder is not
 * writable). */
static void test_cli_simulate_device_written_not_replaced(void)
{
    char own[600];
    (void)snprintf(own, sizeof(own), "%s/null_twin", AENL_TEST_TMP_DIR);
    const char *dev = aenl_test_null_device(own);
    const char *args[] = {"simulate", EXAMPLES "validate_linear_u4.ini", "-o", dev, NULL};
    struct stat before;
    struct stat after;
    cli_result_t r;
    TEST_ASSERT_EQUAL_INT(0, stat(dev, &before));
    TEST_ASSERT_TRUE(S_ISCHR(before.st_mode));
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
    TEST_ASSERT_EQUAL_INT(0, lstat(dev, &after));
    TEST_ASSERT_TRUE_MESSAGE(S_ISCHR(after.st_mode), "the device was replaced");
    TEST_ASSERT_EQUAL_UINT64((uint64_t)before.st_ino, (uint64_t)after.st_ino);
    TEST_ASSERT_TRUE_MESSAGE(cli_no_file_like(".null_twin.tmp"), "a temporary was left");
    (void)remove(own);
}

/* `aenl --version`: one line "aenl MAJOR.MINOR.PATCH" on stdout, exit 0. */
static void test_cli_version(void)
{
    const char *args[] = {"--version", NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(r.out, "aenl ", 5), r.out);
    const char *p = r.out + 5;
    for (int part = 0; part < 3; ++part)
    {
        char *end = NULL;
        (void)strtoul(p, &end, 10);
        TEST_ASSERT_TRUE_MESSAGE(end != p, r.out);
        TEST_ASSERT_EQUAL_INT_MESSAGE(part < 2 ? '.' : '\n', *end, r.out);
        p = end + 1;
    }
    TEST_ASSERT_EQUAL_INT('\0', *p);
    TEST_ASSERT_EQUAL_size_t(strlen(r.out), r.n_out);
    TEST_ASSERT_EQUAL_size_t(0, strlen(r.err));
}

/* The shared conventions of every subcommand: "--opt=value" is "--opt value"; after "--" an
 * argument that starts with '-' is a file name; before it, such a name is an unknown option. */
static void test_cli_option_conventions(void)
{
    const char *spaced[] = {
        "simulate", EXAMPLES "validate_linear_u4.ini", "--rk4", "0.05", "-o", "-", NULL};
    const char *joined[] = {"simulate", EXAMPLES "validate_linear_u4.ini", "--rk4=0.05", "-o", "-",
                            NULL};
    static char a[1 << 17];
    cli_result_t r;
    cli_run(&r, spaced);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_TRUE(r.n_out > 1000 && r.n_out < sizeof(a));
    memcpy(a, r.out, r.n_out);
    const size_t na = r.n_out;
    cli_run(&r, joined);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_size_t(na, r.n_out);
    TEST_ASSERT_EQUAL_MEMORY(a, r.out, na);
    /* an empty value after '=' is a missing value, not the next argument */
    const char *empty[] = {"simulate", EXAMPLES "validate_linear_u4.ini", "--rk4=", "-o", "-",
                           NULL};
    cli_run(&r, empty);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, r.out);
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, r.err_lines, r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);

    static char ini[1 << 14];
    TEST_ASSERT_TRUE(cli_slurp(EXAMPLES "validate_linear_u4.ini", ini, sizeof(ini)) > 10);
    (void)cli_file("-dash.ini", ini);
    const char *dashed[] = {"simulate", "-o", "-", "--", "-dash.ini", NULL};
    cli_run(&r, dashed);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT(0, strncmp(r.out, "t,alpha,xi\n0,0.017453292519943", 30));
    const char *undashed[] = {"simulate", "-dash.ini", "-o", "-", NULL};
    cli_run(&r, undashed);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, "-dash.ini"), r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
}

/* The figure's format follows the output's extension: PNG, SVG and PDF by their signatures. */
static void test_cli_plot_format_from_extension(void)
{
    if (system("command -v gnuplot >/dev/null 2>&1") != 0) /* NOLINT(cert-env33-c) */
    {
        TEST_IGNORE_MESSAGE("gnuplot not installed");
    }
    const char *sim[] = {"simulate", EXAMPLES "validate_linear_u4.ini", "-o", "fmt.csv", NULL};
    cli_result_t r;
    cli_run(&r, sim);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    const char *names[] = {"fmt.png", "fmt.svg", "fmt.PDF"};
    const char *sig[] = {"\x89PNG", "<?xml", "%PDF"};
    for (size_t i = 0; i < 3; ++i)
    {
        const char *plot[] = {"plot", "timeseries", "fmt.csv", "-o", names[i], NULL};
        cli_run(&r, plot);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
        char path[600];
        static char buf[1 << 20];
        (void)snprintf(path, sizeof(path), "%s/%s", AENL_TEST_TMP_DIR, names[i]);
        const size_t n = cli_slurp(path, buf, sizeof(buf));
        TEST_ASSERT_TRUE_MESSAGE(n > 100, names[i]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(buf, sig[i], strlen(sig[i])), names[i]);
    }
    /* column names with spaces and units, as spreadsheets write them */
    (void)cli_file("spaced.csv", "Time [s],pitch angle,plunge\n0,1,2\n0.1,2,3\n0.2,1,1\n");
    const char *spaced[] = {"plot", "timeseries", "spaced.csv", "-o", "spaced.png", NULL};
    cli_run(&r, spaced);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    char path[600];
    static char png[1 << 16];
    (void)snprintf(path, sizeof(path), "%s/spaced.png", AENL_TEST_TMP_DIR);
    TEST_ASSERT_TRUE(cli_slurp(path, png, sizeof(png)) > 100);
    TEST_ASSERT_EQUAL_INT(0, strncmp(png, "\x89PNG", 4));
}

static void test_cli_simulate_same_seed_same_file(void)
{
    const char *a1[] = {"simulate", EXAMPLES "paper_hysteresis_pitch.ini", "-o", "seed_a.csv",
                        NULL};
    const char *a2[] = {"simulate", EXAMPLES "paper_hysteresis_pitch.ini", "-o", "seed_b.csv",
                        NULL};
    static char x[1 << 20], y[1 << 20];
    char pa[600], pb[600];
    cli_result_t r;
    size_t na, nb;
    cli_run(&r, a1);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    cli_run(&r, a2);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    (void)snprintf(pa, sizeof(pa), "%s/seed_a.csv", AENL_TEST_TMP_DIR);
    (void)snprintf(pb, sizeof(pb), "%s/seed_b.csv", AENL_TEST_TMP_DIR);
    na = cli_slurp(pa, x, sizeof(x));
    nb = cli_slurp(pb, y, sizeof(y));
    TEST_ASSERT_TRUE(na > 1000);
    TEST_ASSERT_EQUAL_size_t(na, nb);
    TEST_ASSERT_EQUAL_MEMORY(x, y, na < sizeof(x) ? na : sizeof(x) - 1);
}

static void bad_ini(const char *name, const char *text, const char *where, const char *key)
{
    const char *path = cli_file(name, text);
    const char *args[] = {"simulate", path, "-o", "bad_out.csv", NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, name);
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, r.err_lines, r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, where), r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, key), r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
    TEST_ASSERT_TRUE(cli_no_file_like("bad_out"));
}

#define HEAD "[model]\ntype = airfoil2dof\nustar = 5\n"

static void test_cli_simulate_bad_ini(void)
{
    bad_ini("b_key.ini", HEAD "mus = 3\n[run]\nduration = 5\ndt = 1\n", "b_key.ini:4:", "mus");
    bad_ini("b_sec.ini", HEAD "[runs]\nduration = 5\ndt = 1\n", "b_sec.ini:4:", "[runs]");
    bad_ini("b_req.ini", HEAD "[run]\ndt = 1\n", "b_req.ini:4:", "duration");
    bad_ini("b_neg.ini", HEAD "[run]\nduration = -3\ndt = 1\n", "b_neg.ini:5:", "duration");
    bad_ini("b_dt.ini", HEAD "[run]\nduration = 3\ndt = 0\n", "b_dt.ini:6:", "dt");
    bad_ini("b_nan.ini", HEAD "[initial]\nalpha_deg = NaN\n[run]\nduration = 3\ndt = 1\n",
            "b_nan.ini:5:", "alpha_deg");
}

static cJSON *flutter_json(const char *ini)
{
    const char *args[] = {"flutter", ini, "--json", NULL};
    cli_result_t r;
    cJSON *j;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    j = cJSON_Parse(r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(j, r.out);
    return j;
}

static void test_cli_flutter_json(void)
{
    cJSON *j = flutter_json(EXAMPLES "validate_linear_u4.ini");
    cJSON *in;
    TEST_ASSERT_DOUBLE_WITHIN(1e-4, 6.2851, cJSON_GetObjectItem(j, "speed")->valuedouble);
    TEST_ASSERT_DOUBLE_WITHIN(1e-4, 0.52823, cJSON_GetObjectItem(j, "frequency")->valuedouble);
    TEST_ASSERT_EQUAL_STRING("U*", cJSON_GetObjectItem(j, "unit")->valuestring);
    cJSON_Delete(j);
    j = flutter_json(EXAMPLES "paper_flap_freeplay.ini");
    TEST_ASSERT_DOUBLE_WITHIN(1e-3, 23.897, cJSON_GetObjectItem(j, "speed")->valuedouble);
    TEST_ASSERT_DOUBLE_WITHIN(0.005, 6.09, cJSON_GetObjectItem(j, "frequency")->valuedouble);
    TEST_ASSERT_EQUAL_STRING("m/s", cJSON_GetObjectItem(j, "unit")->valuestring);
    TEST_ASSERT_EQUAL_STRING("Hz", cJSON_GetObjectItem(j, "frequency_unit")->valuestring);
    in = cJSON_GetObjectItem(j, "inner_slope");
    TEST_ASSERT_NOT_NULL(in);
    TEST_ASSERT_DOUBLE_WITHIN(0.005, 6.71, cJSON_GetObjectItem(in, "speed")->valuedouble);
    cJSON_Delete(j);
}

static void test_cli_flutter_sweep_and_errors(void)
{
    const char *args[] = {"flutter", EXAMPLES "validate_linear_u4.ini", "--sweep", "--points", "5",
                          NULL};
    const char *bad[] = {"flutter",
                         cli_file("f_bad.ini", "[model]\ntype = airfoil2dof\nustar = 0\n"), NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_NOT_NULL(strstr(r.out, "flutter speed 6.2850"));
    TEST_ASSERT_NOT_NULL(strstr(r.out, "damping"));
    cli_run(&r, bad);
    TEST_ASSERT_EQUAL_INT(2, r.status);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, "f_bad.ini:3:"), r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_cli_simulate_writes_the_csv_contract);
    RUN_TEST(test_cli_simulate_writes_to_stdout_and_devices);
    RUN_TEST(test_cli_simulate_device_written_not_replaced);
    RUN_TEST(test_cli_simulate_writes_the_force_column);
    RUN_TEST(test_cli_version);
    RUN_TEST(test_cli_option_conventions);
    RUN_TEST(test_cli_plot_format_from_extension);
    RUN_TEST(test_cli_simulate_same_seed_same_file);
    RUN_TEST(test_cli_simulate_bad_ini);
    RUN_TEST(test_cli_flutter_json);
    RUN_TEST(test_cli_flutter_sweep_and_errors);
    return UNITY_END();
}
/* NOLINTEND(bugprone-suspicious-missing-comma) */
