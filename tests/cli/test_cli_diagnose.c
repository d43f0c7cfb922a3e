/* SPDX-License-Identifier: MIT */
/**
 * @file test_cli_diagnose.c
 * @brief `aenl diagnose` end to end: a record simulated from the example truth (2-DOF airfoil,
 *        hidden pitch freeplay, SNR 3) against the example linear baseline names freeplay in
 *        pitch, prints the documented JSON, writes DIR/updated.ini that `aenl simulate` runs as is
 *        and the figure data. Bad input: exit 2, one message on stderr, nothing on stdout, no
 *        output file.
 */
#include "aenl_cli_test.h"

#include <cjson/cJSON.h>
#include <math.h>

#include "unity.h"

/* Path of an example INI under tools/examples (static buffer per call slot). */
static const char *example(const char *name)
{
    static char buf[4][1024];
    static int slot = 0;
    char *p = buf[slot++ % 4];
    (void)snprintf(p, 1024, "%s/tools/examples/%s", AENL_SOURCE_DIR, name);
    return p;
}

void setUp(void)
{
}

void tearDown(void)
{
}

static const char *tmp_path(const char *name)
{
    static char buf[4][512];
    static int slot = 0;
    char *p = buf[slot++ % 4];
    (void)snprintf(p, 512, "%s/%s", AENL_TEST_TMP_DIR, name);
    return p;
}

static void make_record(void)
{
    cli_result_t *r = malloc(sizeof(*r));
    TEST_ASSERT_NOT_NULL(r);
    const char *args[] = {"simulate", example("diagnose_truth_airfoil2dof.ini"), "-o",
                          "measured2.csv", NULL};
    cli_run(r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r->status, r->err);
    free(r);
}

static void test_diagnose_names_freeplay_and_updates(void)
{
    make_record();
    cli_result_t *r = malloc(sizeof(*r));
    TEST_ASSERT_NOT_NULL(r);
    const char *args[] = {"diagnose",
                          "--measured",
                          "measured2.csv",
                          "--model",
                          example("diagnose_base_airfoil2dof.ini"),
                          "--out",
                          "diag2",
                          "--json",
                          "--no-plots",
                          NULL};
    cli_run(r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r->status, r->err);
    cJSON *root = cJSON_Parse(r->out);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, r->out);
    TEST_ASSERT_EQUAL_INT(7, cJSON_GetArraySize(root)); /* schema, aenl_version and five */
    const cJSON *dis = cJSON_GetObjectItemCaseSensitive(root, "disagreement");
    TEST_ASSERT_TRUE(cJSON_IsArray(dis) && cJSON_GetArraySize(dis) >= 1);
    const cJSON *d0 = cJSON_GetArrayItem(dis, 0);
    TEST_ASSERT_TRUE(cJSON_IsString(cJSON_GetObjectItemCaseSensitive(d0, "channel")));
    TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(d0, "band")));
    TEST_ASSERT_TRUE(cJSON_IsString(cJSON_GetObjectItemCaseSensitive(d0, "signature")));
    TEST_ASSERT_TRUE(cJSON_GetObjectItemCaseSensitive(d0, "significance")->valuedouble > 3.0);
    const cJSON *me = cJSON_GetObjectItemCaseSensitive(root, "missing_effect");
    TEST_ASSERT_EQUAL_STRING("freeplay", cJSON_GetObjectItemCaseSensitive(me, "type")->valuestring);
    TEST_ASSERT_EQUAL_STRING("pitch", cJSON_GetObjectItemCaseSensitive(me, "dof")->valuestring);
    const cJSON *params = cJSON_GetObjectItemCaseSensitive(me, "params");
    const double deg = 3.14159265358979323846 / 180.0;
    TEST_ASSERT_DOUBLE_WITHIN(0.15 * 0.5 * deg, 0.5 * deg,
                              cJSON_GetObjectItemCaseSensitive(params, "delta")->valuedouble);
    TEST_ASSERT_DOUBLE_WITHIN(0.15 * 0.2 * deg, 0.2 * deg,
                              cJSON_GetObjectItemCaseSensitive(params, "alpha_f")->valuedouble);
    /* The summary fit's standard errors, under the parameters' keys. */
    const cJSON *sd = cJSON_GetObjectItemCaseSensitive(me, "params_sd");
    TEST_ASSERT_TRUE(cJSON_IsObject(sd));
    const cJSON *sd_delta = cJSON_GetObjectItemCaseSensitive(sd, "delta");
    TEST_ASSERT_TRUE(cJSON_IsNumber(sd_delta));
    TEST_ASSERT_TRUE(sd_delta->valuedouble > 0.0 && sd_delta->valuedouble < 0.1 * 0.5 * deg);
    const double before = cJSON_GetObjectItemCaseSensitive(root, "gap_before")->valuedouble;
    const double after = cJSON_GetObjectItemCaseSensitive(root, "gap_after")->valuedouble;
    TEST_ASSERT_TRUE(before >= 5.0 * after);
    TEST_ASSERT_EQUAL_STRING("diag2/updated.ini",
                             cJSON_GetObjectItemCaseSensitive(root, "updated_model")->valuestring);
    cJSON_Delete(root);
    static const char *const files[] = {"diag2/updated.ini",      "diag2/report.txt",
                                        "diag2/gaps.csv",         "diag2/candidates.csv",
                                        "diag2/curves_alpha.csv", "diag2/spectrum_xi.csv",
                                        "diag2/timeseries.csv"};
    for (size_t i = 0; i < sizeof(files) / sizeof(files[0]); ++i)
    {
        TEST_ASSERT_TRUE_MESSAGE(cli_exists(tmp_path(files[i])), files[i]);
    }
    /* The updated model runs as is. */
    const char *sim[] = {"simulate", "diag2/updated.ini", "-o", "updated_sim.csv", NULL};
    cli_run(r, sim);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r->status, r->err);
    TEST_ASSERT_TRUE(cli_exists(tmp_path("updated_sim.csv")));
    free(r);
}

/* A free decay released from a state the baseline INI does not give: the state is fitted to
 * the record, reported with standard errors (within 4 of them of the release), the linear
 * baseline agrees, and the updated INI starts from the fit and says it is one. An [initial]
 * estimate that is not a truth value is refused, and so is estimate = true under turbulence. */
static void test_diagnose_fits_a_decays_release(void)
{
    static const char *const model = "[model]\ntype = airfoil2dof\nustar = 4\nzeta_alpha = 0.01\n"
                                     "zeta_xi = 0.01\n";
    static const char *const run = "[run]\nduration = 1999.5\ndt = 0.5\n";
    char truth[512], base[512];
    (void)snprintf(truth, sizeof(truth),
                   "%s[initial]\nalpha_deg = 2\nxi = 0.01\n%s[noise]\nsnr = 10\nseed = 3\n", model,
                   run);
    (void)snprintf(base, sizeof(base), "%s%s", model, run);
    (void)cli_file("decay_truth.ini", truth);
    (void)cli_file("decay_base.ini", base);
    cli_result_t *r = malloc(sizeof(*r));
    TEST_ASSERT_NOT_NULL(r);
    const char *sim[] = {"simulate", "decay_truth.ini", "-o", "decay.csv", NULL};
    cli_run(r, sim);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r->status, r->err);
    const char *args[] = {"diagnose", "--measured", "decay.csv", "--model",    "decay_base.ini",
                          "--out",    "diagD",      "--json",    "--no-plots", NULL};
    cli_run(r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r->status, r->err);
    cJSON *root = cJSON_Parse(r->out);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, r->out);
    const cJSON *me = cJSON_GetObjectItemCaseSensitive(root, "missing_effect");
    TEST_ASSERT_EQUAL_STRING("none", cJSON_GetObjectItemCaseSensitive(me, "type")->valuestring);
    const cJSON *in = cJSON_GetObjectItemCaseSensitive(root, "initial_state");
    TEST_ASSERT_TRUE(cJSON_IsObject(in));
    const cJSON *state = cJSON_GetObjectItemCaseSensitive(in, "state");
    const cJSON *sd = cJSON_GetObjectItemCaseSensitive(in, "sd");
    const char *const keys[] = {"alpha", "xi", "alpha_dot", "xi_dot"};
    const double want[] = {2.0 * 3.14159265358979323846 / 180.0, 0.01, 0.0, 0.0};
    for (size_t k = 0; k < 4u; ++k)
    {
        const double v = cJSON_GetObjectItemCaseSensitive(state, keys[k])->valuedouble;
        const double e = cJSON_GetObjectItemCaseSensitive(sd, keys[k])->valuedouble;
        TEST_ASSERT_TRUE_MESSAGE(e > 0.0 && fabs(v - want[k]) < 4.0 * e, keys[k]);
    }
    cJSON_Delete(root);
    static char ini[16384];
    TEST_ASSERT_TRUE(cli_slurp(tmp_path("diagD/updated.ini"), ini, sizeof(ini)) > 0u);
    TEST_ASSERT_NOT_NULL(strstr(ini, "estimate = true"));
    free(r);
    (void)cli_file("decay_bad.ini", "[model]\ntype = airfoil2dof\nustar = 4\n"
                                    "[initial]\nestimate = maybe\n[run]\nduration = 1999.5\n"
                                    "dt = 0.5\n");
    const char *bad[] = {"diagnose", "--measured", "decay.csv", "--model", "decay_bad.ini", NULL};
    cli_expect_refused(bad, "estimate");
    /* under turbulence there is no release to fit */
    (void)cli_file("decay_turb.ini", "[model]\ntype = airfoil2dof\nustar = 4\n"
                                     "[initial]\nestimate = true\n[excitation]\n"
                                     "type = turbulence\nintensity = 0.005\n[run]\n"
                                     "duration = 1999.5\ndt = 0.5\n");
    const char *turb[] = {"diagnose", "--measured", "decay.csv", "--model", "decay_turb.ini", NULL};
    cli_expect_refused(turb, "turbulence");
}

/* exit 2, exactly one line on stderr containing `want`, nothing on stdout */
static void test_diagnose_bad_input(void)
{
    make_record();
    const char *base = example("diagnose_base_airfoil2dof.ini");
    const char *no_model[] = {"diagnose", "--measured", "measured2.csv", NULL};
    cli_expect_refused(no_model, "--model");
    const char *unknown[] = {"diagnose", "--measured", "measured2.csv", "--model", base,
                             "--bogus",  NULL};
    cli_expect_refused(unknown, "--bogus");
    const char *missing_file[] = {"diagnose", "--measured", "nope.csv", "--model", base, NULL};
    cli_expect_refused(missing_file, "nope.csv");
    const char *few[] = {"diagnose", "--measured", "measured2.csv",
                         "--model",  base,         "--summary-records",
                         "10",       NULL};
    cli_expect_refused(few, "--summary-records");
    /* The record of the wrong model: no channel 'h'. */
    const char *wrong_model[] = {"diagnose",
                                 "--measured",
                                 "measured2.csv",
                                 "--model",
                                 example("diagnose_base_section3dof.ini"),
                                 NULL};
    cli_expect_refused(wrong_model, "no column 'h'");
    /* A record at another step than the model's dt. */
    const char *csv = cli_file("short_dt.csv", "t,alpha,xi\n");
    FILE *f = fopen(csv, "a");
    TEST_ASSERT_NOT_NULL(f);
    for (int i = 0; i < 1000; ++i)
    {
        fprintf(f, "%g,%g,%g\n", 0.25 * i, sin(0.1 * i), cos(0.07 * i));
    }
    (void)fclose(f);
    const char *wrong_dt[] = {"diagnose", "--measured", "short_dt.csv", "--model", base, NULL};
    cli_expect_refused(wrong_dt, "dt");
    /* --out into a folder that cannot be created: no file anywhere. */
    const char *bad_out[] = {"diagnose",    "--measured", "measured2.csv", "--model", base, "--out",
                             "no/such/dir", "--no-plots", "--refine",      "0",       NULL};
    cli_expect_refused(bad_out, "no/such/dir");
    TEST_ASSERT_TRUE(cli_no_file_like("no"));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_diagnose_names_freeplay_and_updates);
    RUN_TEST(test_diagnose_fits_a_decays_release);
    RUN_TEST(test_diagnose_bad_input);
    return UNITY_END();
}
