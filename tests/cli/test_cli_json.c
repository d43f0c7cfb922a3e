/* SPDX-License-Identifier: MIT */
/**
 * @file test_cli_json.c
 * @brief Every JSON output against its schema in docs/schema: identify (conditional moments),
 *        identify --method test (with a known input and linear controls), flutter (with and
 *        without --sweep), fit and diagnose. The schema check itself is shown to fail on a
 *        wrong type, a missing member, a member the schema does not name, a value outside an
 *        enumeration or a range, and a schema keyword it does not implement.
 */
#include "aenl_cli_test.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "aenl_schema_check.h"
#include "aenl_test_sanitized.h"
#include "unity.h"

#define EXAMPLES AENL_SOURCE_DIR "/tools/examples/"
#define SCHEMAS  AENL_SOURCE_DIR "/docs/schema/"
/* NOLINTBEGIN(bugprone-suspicious-missing-comma) */

void setUp(void)
{
}

void tearDown(void)
{
}

static cJSON *load_schema(const char *name)
{
    static char text[1 << 16];
    char path[600];
    (void)snprintf(path, sizeof(path), "%s%s.schema.json", SCHEMAS, name);
    const size_t n = cli_slurp(path, text, sizeof(text));
    TEST_ASSERT_TRUE_MESSAGE(n > 0 && n < sizeof(text) - 1u, path);
    cJSON *s = cJSON_Parse(text);
    TEST_ASSERT_NOT_NULL_MESSAGE(s, path);
    return s;
}

/* The command's stdout is one JSON document that satisfies the named schema (and holds the text
 * must, unless NULL); the document, for the caller to look into and delete. The outputs'
 * memory safety is checked elsewhere (valgrind of every subcommand), so the sanitizer build,
 * where the runs take minutes, leaves this contract to the strict build. */
static cJSON *check_output(const char *schema, const char *const *args, const char *must)
{
    AENL_PLAIN_BUILD_ONLY("the JSON contract: checked in the strict build");
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    cJSON *doc = cJSON_Parse(r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(doc, r.out);
    cJSON *s = load_schema(schema);
    schema_fail_t f = {{0}, {0}};
    memset(&f, 0, sizeof(f));
    const int ok = schema_check(s, s, doc, "", &f);
    char msg[600];
    (void)snprintf(msg, sizeof(msg), "%s: %s at %s", schema, f.why, f.where);
    TEST_ASSERT_TRUE_MESSAGE(ok, msg);
    cJSON_Delete(s);
    TEST_ASSERT_TRUE_MESSAGE(must == NULL || strstr(r.out, must) != NULL, r.out);
    return doc;
}

static const char *simulated(const char *ini, const char *csv)
{
    const char *args[] = {"simulate", ini, "-o", csv, NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    return csv;
}

static void test_json_identify_and_flutter(void)
{
    const char *rec = simulated(EXAMPLES "paper_hysteresis_pitch.ini", "j_hyst.csv");
    const char *id[] = {"identify", rec, "--method", "moments", "--json", NULL};
    cJSON_Delete(check_output("identify", id, NULL));
    const char *fl[] = {"flutter", EXAMPLES "paper_polynomial_pitch.ini", "--json", NULL};
    cJSON_Delete(check_output("flutter", fl, NULL));
    const char *fl3[] = {
        "flutter", EXAMPLES "section3dof_multisine.ini", "--json", "--sweep", "--points", "3",
        NULL};
    cJSON_Delete(check_output("flutter", fl3, NULL));
}

/* The CSV AENL_TEST_TMP_DIR/csv without its first column, as AENL_TEST_TMP_DIR/name. */
static const char *without_first_column(const char *csv, const char *name)
{
    static char in[1 << 20], out[1 << 20];
    char path[600];
    (void)snprintf(path, sizeof(path), "%s/%s", AENL_TEST_TMP_DIR, csv);
    const size_t n = cli_slurp(path, in, sizeof(in));
    TEST_ASSERT_TRUE_MESSAGE(n > 0 && n < sizeof(in) - 1u, path);
    size_t k = 0;
    for (const char *l = in; *l != '\0';)
    {
        const char *comma = strchr(l, ',');
        const char *nl = strchr(l, '\n');
        const char *from = comma != NULL && (nl == NULL || comma < nl) ? comma + 1 : l;
        const size_t len = nl != NULL ? (size_t)(nl - from) + 1u : strlen(from);
        memcpy(out + k, from, len);
        k += len;
        l = from + len;
    }
    out[k] = '\0';
    return cli_file(name, out);
}

/* A test's JSON holds the record's step (dt; null when want_dt is NaN) and its notes (one of
 * them containing note, unless NULL), and each channel's period in samples and in the time
 * column's unit. */
static void check_step_and_notes(const cJSON *doc, double want_dt, const char *note)
{
    const cJSON *dt = cJSON_GetObjectItemCaseSensitive(doc, "dt");
    const cJSON *notes = cJSON_GetObjectItemCaseSensitive(doc, "notes");
    TEST_ASSERT_NOT_NULL_MESSAGE(dt, "dt");
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsArray(notes), "notes");
    if (isnan(want_dt))
    {
        TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNull(dt), "dt without a time column");
    }
    else
    {
        TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(dt), "dt");
        TEST_ASSERT_DOUBLE_WITHIN(1e-9 * want_dt, want_dt, dt->valuedouble);
    }
    int found = note == NULL;
    const cJSON *x = NULL;
    cJSON_ArrayForEach(x, notes)
    {
        TEST_ASSERT_TRUE_MESSAGE(cJSON_IsString(x), "a note");
        found |= note != NULL && strstr(x->valuestring, note) != NULL;
        /* a record with a time column gets no note that it has none */
        TEST_ASSERT_TRUE_MESSAGE(note != NULL ||
                                     strstr(x->valuestring, "has no time column") == NULL,
                                 "a no-time note on a record with a time column");
    }
    TEST_ASSERT_TRUE_MESSAGE(found, note != NULL ? note : "notes");
    const cJSON *c = NULL;
    cJSON_ArrayForEach(c, cJSON_GetObjectItemCaseSensitive(doc, "channels"))
    {
        const cJSON *spp = cJSON_GetObjectItemCaseSensitive(c, "samples_per_period");
        const cJSON *ps = cJSON_GetObjectItemCaseSensitive(c, "period_samples");
        const cJSON *pt = cJSON_GetObjectItemCaseSensitive(c, "period_s");
        TEST_ASSERT_TRUE(cJSON_IsNumber(spp) && cJSON_IsNumber(ps));
        TEST_ASSERT_EQUAL_DOUBLE(spp->valuedouble, ps->valuedouble);
        if (isnan(want_dt))
        {
            TEST_ASSERT_TRUE(cJSON_IsNull(pt));
        }
        else
        {
            TEST_ASSERT_TRUE(cJSON_IsNumber(pt));
            TEST_ASSERT_DOUBLE_WITHIN(1e-9 * pt->valuedouble, spp->valuedouble * want_dt,
                                      pt->valuedouble);
        }
    }
}

static void test_json_identify_test_with_input_and_controls(void)
{
    const char *ini = cli_file("j_ms.ini", "[model]\ntype = section3dof\nvelocity = 12\n\n"
                                           "[flap]\nlaw = freeplay\ndelta_deg = 2\n"
                                           "alpha_f_deg = -1\n\n[excitation]\ntype = multisine\n"
                                           "dof = pitch\nrms_deg = 0.5\nf_min = 1\nf_max = 20\n"
                                           "period = 2\nseed = 3\n\n[run]\nduration = 4\n"
                                           "dt = 0.002\n\n[noise]\nsnr = 10\nseed = 7\n");
    const char *rec = simulated(ini, "j_ms.csv");
    /* the test is identify's default method */
    const char *plain[] = {"identify", rec, "--json", NULL};
    cJSON *doc = check_output("identify-test", plain, NULL);
    check_step_and_notes(doc, 0.002, NULL);
    cJSON_Delete(doc);
    /* the same record without its time column: no step, and the note that says so */
    const char *plain_nt[] = {"identify", without_first_column(rec, "j_ms_nt.csv"), "--json", NULL};
    doc = check_output("identify-test", plain_nt, NULL);
    check_step_and_notes(doc, (double)NAN, "has no time column");
    cJSON_Delete(doc);
    const char *full[] = {"identify", rec,      "--method",   "test", "--input",
                          "f_pitch",  "--json", "--controls", "1",    NULL};
    cJSON_Delete(check_output("identify-test", full, NULL));
    /* the same section without measurement noise: its channels are dithered, and say so */
    const char *ini0 = cli_file("j_ms0.ini", "[model]\ntype = section3dof\nvelocity = 12\n\n"
                                             "[excitation]\ntype = multisine\ndof = pitch\n"
                                             "rms_deg = 0.5\nf_min = 1\nf_max = 20\nperiod = 2\n"
                                             "seed = 3\n\n[run]\nduration = 4\ndt = 0.002\n");
    const char *rec0 = simulated(ini0, "j_ms0.csv");
    const char *clean[] = {"identify", rec0, "--input", "f_pitch", "--json", NULL};
    cJSON_Delete(check_output("identify-test", clean, "\"dithered\""));
}

/* A train of pitch kicks (19 after the start, SNR 10) declared driven by impulses: the document
 * says that the test ran on the jump model, with one impulse for each kick, and the record is
 * linear; undeclared, the same record's document has no such member. */
static void test_json_identify_test_impulsive(void)
{
    const char *ini = cli_file("j_kicks.ini", "[model]\ntype = airfoil2dof\nustar = 4\n\n"
                                              "[excitation]\ntype = kicks\ndof = pitch\n"
                                              "every = 150\nrate = 0.002\nrate_max = 0.003\n"
                                              "sign = random\nseed = 11\n\n[run]\n"
                                              "duration = 3000\ndt = 0.5\n\n[noise]\nsnr = 10\n"
                                              "seed = 12\n");
    const char *rec = simulated(ini, "j_kicks.csv");
    const char *declared[] = {"identify", rec, "--impulsive", "--json", NULL};
    cJSON *doc = check_output("identify-test", declared, "\"jumps\"");
    const cJSON *model = cJSON_GetObjectItemCaseSensitive(doc, "model");
    TEST_ASSERT_TRUE(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(model, "jumps")));
    const int imp = cJSON_GetObjectItemCaseSensitive(model, "impulses")->valueint;
    TEST_ASSERT_TRUE_MESSAGE(imp >= 17 && imp <= 21, "one impulse per kick");
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(doc, "verdict");
    TEST_ASSERT_EQUAL_STRING("linear", cJSON_GetObjectItemCaseSensitive(v, "class")->valuestring);
    cJSON_Delete(doc);
    const char *plain[] = {"identify", rec, "--json", NULL};
    doc = check_output("identify-test", plain, NULL);
    model = cJSON_GetObjectItemCaseSensitive(doc, "model");
    TEST_ASSERT_NULL(cJSON_GetObjectItemCaseSensitive(model, "jumps"));
    cJSON_Delete(doc);
}

static void test_json_fit_and_diagnose(void)
{
    const char *rec = simulated(EXAMPLES "paper_polynomial_pitch.ini", "j_poly.csv");
    const char *fit[] = {"fit", rec, "--thresholds", "alpha:0.0", "--iter", "5", "--json", NULL};
    cJSON_Delete(check_output("fit", fit, NULL));
    const char *boot[] = {"fit",         rec, "--thresholds", "alpha:0.0", "--iter", "5",
                          "--bootstrap", "2", "--json",       NULL};
    cJSON_Delete(check_output("fit", boot, NULL));
    const char *meas = simulated(EXAMPLES "diagnose_truth_airfoil2dof.ini", "j_dg.csv");
    const char *dg[] = {
        "diagnose", "--measured",  meas, "--model",    EXAMPLES "diagnose_base_airfoil2dof.ini",
        "--json",   "--max-evals", "20", "--no-plots", NULL};
    cJSON_Delete(check_output("diagnose", dg, NULL));
    /* a free decay whose release the baseline leaves to the fit: initial_state */
    (void)cli_file("j_decay_truth.ini", "[model]\ntype = airfoil2dof\nustar = 4\n[initial]\n"
                                        "alpha_deg = 2\n[run]\nduration = 1499.5\ndt = 0.5\n"
                                        "[noise]\nsnr = 10\n");
    (void)cli_file("j_decay_base.ini",
                   "[model]\ntype = airfoil2dof\nustar = 4\n[run]\nduration = 1499.5\ndt = 0.5\n");
    const char *decay = simulated("j_decay_truth.ini", "j_decay.csv");
    const char *dd[] = {"diagnose", "--measured",  decay, "--model",    "j_decay_base.ini",
                        "--json",   "--max-evals", "20",  "--no-plots", NULL};
    cJSON_Delete(check_output("diagnose", dd, "\"initial_state\""));
    /* a baseline that runs away at once cannot be fitted: the first sample at rest, no errors */
    (void)cli_file("j_decay_soft.ini", "[model]\ntype = airfoil2dof\nustar = 4\n[pitch]\n"
                                       "law = polynomial\ncoeffs = 1, 0, -100000\n[run]\n"
                                       "duration = 1499.5\ndt = 0.5\n");
    const char *ds[] = {"diagnose", "--measured",  decay, "--model",    "j_decay_soft.ini",
                        "--json",   "--max-evals", "20",  "--no-plots", "--summary-records",
                        "0",        NULL};
    cJSON_Delete(check_output("diagnose", ds, "\"window\":0"));
}

/* The check fails where it should: each mutation of a valid document, and an unknown keyword. */
static void test_schema_check_rejects(void)
{
    cJSON *s = load_schema("flutter");
    static const char *const bad[] = {
        "{\"schema\":\"aenl-flutter/1\",\"aenl_version\":\"0\",\"file\":\"f\",\"model\":"
        "\"airfoil2dof\",\"speed\":\"fast\",\"frequency\":1,\"unit\":\"U*\",\"frequency_unit\":"
        "\"Hz\"}",
        "{\"schema\":\"aenl-flutter/1\",\"aenl_version\":\"0\",\"file\":\"f\",\"model\":"
        "\"airfoil2dof\",\"frequency\":1,\"unit\":\"U*\",\"frequency_unit\":\"Hz\"}",
        "{\"schema\":\"aenl-flutter/1\",\"aenl_version\":\"0\",\"file\":\"f\",\"model\":"
        "\"airfoil2dof\",\"speed\":1,\"frequency\":1,\"unit\":\"U*\",\"frequency_unit\":\"Hz\","
        "\"extra\":1}",
        "{\"schema\":\"aenl-flutter/1\",\"aenl_version\":\"0\",\"file\":\"f\",\"model\":"
        "\"airfoil3dof\",\"speed\":1,\"frequency\":1,\"unit\":\"U*\",\"frequency_unit\":\"Hz\"}",
        "{\"schema\":\"aenl-flutter/1\",\"aenl_version\":\"0\",\"file\":\"f\",\"model\":"
        "\"airfoil2dof\",\"speed\":-1,\"frequency\":1,\"unit\":\"U*\",\"frequency_unit\":\"Hz\"}"};
    static const char *const why[] = {"wrong type", "missing required member speed",
                                      "member not in the schema", "enumerated", "minimum"};
    const char *good = "{\"schema\":\"aenl-flutter/1\",\"aenl_version\":\"0\",\"file\":\"f\","
                       "\"model\":\"airfoil2dof\",\"speed\":1,\"frequency\":null,\"unit\":\"U*\","
                       "\"frequency_unit\":\"Hz\"}";
    schema_fail_t f = {{0}, {0}};
    cJSON *doc = cJSON_Parse(good);
    TEST_ASSERT_TRUE_MESSAGE(schema_check(s, s, doc, "", &f), f.why);
    cJSON_Delete(doc);
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); ++i)
    {
        doc = cJSON_Parse(bad[i]);
        TEST_ASSERT_NOT_NULL(doc);
        memset(&f, 0, sizeof(f));
        TEST_ASSERT_FALSE_MESSAGE(schema_check(s, s, doc, "", &f), bad[i]);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(f.why, why[i]), f.why);
        cJSON_Delete(doc);
    }
    cJSON_Delete(s);
    cJSON *odd = cJSON_Parse("{\"type\":\"object\",\"pattern\":\"x\"}");
    doc = cJSON_Parse("{}");
    TEST_ASSERT_FALSE(schema_check(odd, odd, doc, "", &f));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(f.why, "pattern"), f.why);
    cJSON_Delete(odd);
    cJSON_Delete(doc);
}

/* NOLINTEND(bugprone-suspicious-missing-comma) */

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_schema_check_rejects);
    RUN_TEST(test_json_identify_and_flutter);
    RUN_TEST(test_json_identify_test_with_input_and_controls);
    RUN_TEST(test_json_identify_test_impulsive);
    RUN_TEST(test_json_fit_and_diagnose);
    return UNITY_END();
}
