/* SPDX-License-Identifier: MIT */
/**
 * @file test_cli_identify.c
 * @brief `aenl identify` end to end: the JSON object of docs/identify.md (every key and no
 *        other, types, class names from the allowed set, ascending switching points, a verdict
 *        consistent with its channel), the table, --channel, --plot (three figures per channel,
 *        folder created, nothing left on failure), and bad input (exit 2, one line on stderr
 *        naming what and where, nothing on stdout, no output). Content is checked only where it
 *        is unambiguous: the paper's 3-DOF flap freeplay (delta = 2 deg, SNR 3) is freeplay in
 *        beta with its points near -+1 deg, a linear turbulence record is linear, a linear
 *        decay train of kicked releases is linear with its impulses reported.
 */
#include "aenl_cli_test.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>

#include "aenl_evalsuite.h"
#include "aenl_test_sanitized.h"
#include "unity.h"

#define DEG 0.017453292519943295

void setUp(void)
{
}

void tearDown(void)
{
}

/* Like cli_file(), with a pool large enough for every path a test holds at once. */
static const char *put_file(const char *name, const char *text)
{
    static char paths[48][512];
    static int slot = 0;
    char *p = paths[slot++ % 48];
    (void)snprintf(p, 512, "%s", cli_file(name, text));
    return p;
}

/* ---- records ------------------------------------------------------------------------------ */

/* The source tree's root (set by the build). */
static const char *source_root(void)
{
    return AENL_SOURCE_DIR;
}

/* `aenl simulate INI -o NAME` into the test folder (once per name); the full path. */
static const char *simulate(const char *ini, const char *name)
{
    static char paths[4][512];
    static int slot = 0;
    char *p = paths[slot++ % 4];
    (void)snprintf(p, 512, "%s/%s", AENL_TEST_TMP_DIR, name);
    if (!cli_exists(p))
    {
        const char *args[] = {"simulate", ini, "-o", name, NULL};
        cli_result_t r;
        cli_run(&r, args);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    }
    return p;
}

/* The paper's flap freeplay (3-DOF section, gap -1 .. +1 deg, SNR 3): t,h,alpha,beta. */
static const char *flap_record(void)
{
    char ini[600];
    (void)snprintf(ini, sizeof(ini), "%s/tools/examples/paper_flap_freeplay.ini", source_root());
    return simulate(ini, "id_flap.csv");
}

/* The same section, linear in every DOF, below flutter and driven by turbulence, SNR 10. */
static const char *linear_record(void)
{
    const char *ini = cli_file("id_linear.ini", "[model]\ntype = section3dof\nvelocity = 12\n\n"
                                                "[excitation]\ntype = turbulence\n"
                                                "intensity = 0.005\nlength_scale = 0.25\n"
                                                "seed = 3\n\n[run]\nduration = 20\ndt = 0.002\n\n"
                                                "[noise]\nsnr = 10\nseed = 5\n");
    return simulate(ini, "id_linear.csv");
}

/* ---- the JSON contract -------------------------------------------------------------------- */

static int is_class(const cJSON *s)
{
    static const char *const k_classes[] = {"linear", "polynomial", "freeplay", "hysteresis",
                                            "insufficient"};
    if (!cJSON_IsString(s))
    {
        return 0;
    }
    for (size_t i = 0; i < sizeof(k_classes) / sizeof(k_classes[0]); ++i)
    {
        if (strcmp(s->valuestring, k_classes[i]) == 0)
        {
            return 1;
        }
    }
    return 0;
}

/* Every key of `obj` is one of `keys` (n of them) and every one of them is there. */
static void check_keys(const cJSON *obj, const char *const *keys, size_t n, const char *what)
{
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsObject(obj), what);
    const cJSON *item = NULL;
    size_t seen = 0;
    cJSON_ArrayForEach(item, obj)
    {
        int known = 0;
        for (size_t i = 0; i < n; ++i)
        {
            known |= (strcmp(item->string, keys[i]) == 0);
        }
        char msg[256];
        (void)snprintf(msg, sizeof(msg), "%s: unexpected key '%s'", what, item->string);
        TEST_ASSERT_TRUE_MESSAGE(known, msg);
        seen++;
    }
    for (size_t i = 0; i < n; ++i)
    {
        char msg[256];
        (void)snprintf(msg, sizeof(msg), "%s: no key '%s'", what, keys[i]);
        TEST_ASSERT_NOT_NULL_MESSAGE(cJSON_GetObjectItemCaseSensitive(obj, keys[i]), msg);
    }
    TEST_ASSERT_EQUAL_size_t_MESSAGE(n, seen, what);
}

/* An array of finite numbers in ascending order (null allowed where `nulls`). */
static void check_numbers(const cJSON *a, int ascending, int nulls, const char *what)
{
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsArray(a), what);
    double prev = -HUGE_VAL;
    const cJSON *v = NULL;
    cJSON_ArrayForEach(v, a)
    {
        if (nulls && cJSON_IsNull(v))
        {
            continue;
        }
        TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(v) && isfinite(v->valuedouble), what);
        if (ascending)
        {
            TEST_ASSERT_TRUE_MESSAGE(v->valuedouble >= prev, what);
            prev = v->valuedouble;
        }
    }
}

static void check_confidence(const cJSON *c, const char *what)
{
    TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(c), what);
    TEST_ASSERT_TRUE_MESSAGE(c->valuedouble >= 0.0 && c->valuedouble <= 1.0, what);
}

/* The whole object, as docs/identify.md gives it; returns the verdict's channel object or NULL. */
static const cJSON *check_contract(const cJSON *root, const char *file, int n_channels)
{
    static const char *const k_top[] = {"schema",  "aenl_version", "file",     "rows",
                                        "verdict", "channels",     "impulses", "limit_cycle",
                                        "model",   "notes"};
    static const char *const k_verdict[] = {"class",      "channel",  "hardening", "switch_points",
                                            "confidence", "by_model", "guess"};
    static const char *const k_channel[] = {
        "name",       "class",     "hardening",    "switch_points", "switch_point_std",
        "confidence", "bandwidth", "bandwidth_by", "period",        "noise",
        "lags"};
    check_keys(root, k_top, 10, "top level");
    const cJSON *notes = cJSON_GetObjectItemCaseSensitive(root, "notes");
    TEST_ASSERT_TRUE(cJSON_IsArray(notes));
    const cJSON *note = NULL;
    cJSON_ArrayForEach(note, notes)
    {
        TEST_ASSERT_TRUE(cJSON_IsString(note));
    }
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(root, "file");
    TEST_ASSERT_TRUE(cJSON_IsString(f));
    TEST_ASSERT_EQUAL_STRING(file, f->valuestring);

    const cJSON *chans = cJSON_GetObjectItemCaseSensitive(root, "channels");
    TEST_ASSERT_TRUE(cJSON_IsArray(chans));
    TEST_ASSERT_EQUAL_INT(n_channels, cJSON_GetArraySize(chans));
    const cJSON *ch = NULL;
    cJSON_ArrayForEach(ch, chans)
    {
        check_keys(ch, k_channel, 11, "channel");
        const cJSON *name = cJSON_GetObjectItemCaseSensitive(ch, "name");
        TEST_ASSERT_TRUE(cJSON_IsString(name));
        const char *what = name->valuestring;
        const cJSON *cls = cJSON_GetObjectItemCaseSensitive(ch, "class");
        TEST_ASSERT_TRUE_MESSAGE(is_class(cls), what);
        const cJSON *pts = cJSON_GetObjectItemCaseSensitive(ch, "switch_points");
        const cJSON *std = cJSON_GetObjectItemCaseSensitive(ch, "switch_point_std");
        check_numbers(pts, 1, 0, what);
        check_numbers(std, 0, 1, what);
        TEST_ASSERT_EQUAL_INT_MESSAGE(cJSON_GetArraySize(pts), cJSON_GetArraySize(std), what);
        const cJSON *s = NULL;
        cJSON_ArrayForEach(s, std)
        {
            TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNull(s) || s->valuedouble >= 0.0, what);
        }
        const char *c = cls->valuestring;
        if (strcmp(c, "linear") == 0 || strcmp(c, "polynomial") == 0 ||
            strcmp(c, "insufficient") == 0)
        {
            TEST_ASSERT_EQUAL_INT_MESSAGE(0, cJSON_GetArraySize(pts), what);
        }
        if (strcmp(c, "freeplay") == 0)
        {
            TEST_ASSERT_TRUE_MESSAGE(cJSON_GetArraySize(pts) >= 1, what);
        }
        check_confidence(cJSON_GetObjectItemCaseSensitive(ch, "confidence"), what);
        const cJSON *bw = cJSON_GetObjectItemCaseSensitive(ch, "bandwidth");
        TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(bw) && bw->valuedouble > 0.0, what);
        const cJSON *lags = cJSON_GetObjectItemCaseSensitive(ch, "lags");
        check_numbers(lags, 1, 0, what);
        TEST_ASSERT_TRUE_MESSAGE(cJSON_GetArraySize(lags) >= 1, what);
        const cJSON *l = NULL;
        cJSON_ArrayForEach(l, lags)
        {
            TEST_ASSERT_TRUE_MESSAGE(l->valuedouble >= 1.0 &&
                                         fabs(l->valuedouble - floor(l->valuedouble)) < 1e-12,
                                     what);
        }
    }

    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "verdict");
    check_keys(v, k_verdict, 7, "verdict");
    const cJSON *vcls = cJSON_GetObjectItemCaseSensitive(v, "class");
    TEST_ASSERT_TRUE(is_class(vcls));
    const cJSON *vpts = cJSON_GetObjectItemCaseSensitive(v, "switch_points");
    check_numbers(vpts, 1, 0, "verdict");
    check_confidence(cJSON_GetObjectItemCaseSensitive(v, "confidence"), "verdict");
    const cJSON *vch = cJSON_GetObjectItemCaseSensitive(v, "channel");
    if (cJSON_IsNull(vch))
    {
        /* no channel named: linear or insufficient, and then no switching points */
        TEST_ASSERT_TRUE(strcmp(vcls->valuestring, "linear") == 0 ||
                         strcmp(vcls->valuestring, "insufficient") == 0);
        TEST_ASSERT_EQUAL_INT(0, cJSON_GetArraySize(vpts));
        cJSON_ArrayForEach(ch, chans)
        {
            const char *c = cJSON_GetObjectItemCaseSensitive(ch, "class")->valuestring;
            TEST_ASSERT_TRUE(strcmp(c, "linear") == 0 || strcmp(c, "insufficient") == 0);
        }
        return NULL;
    }
    /* a channel named: one of the channels, same class and points */
    TEST_ASSERT_TRUE(cJSON_IsString(vch));
    const cJSON *named = NULL;
    cJSON_ArrayForEach(ch, chans)
    {
        if (strcmp(cJSON_GetObjectItemCaseSensitive(ch, "name")->valuestring, vch->valuestring) ==
            0)
        {
            named = ch;
        }
    }
    TEST_ASSERT_NOT_NULL_MESSAGE(named, "the verdict names no channel of the list");
    TEST_ASSERT_EQUAL_STRING(cJSON_GetObjectItemCaseSensitive(named, "class")->valuestring,
                             vcls->valuestring);
    TEST_ASSERT_FALSE(strcmp(vcls->valuestring, "linear") == 0 ||
                      strcmp(vcls->valuestring, "insufficient") == 0);
    const cJSON *npts = cJSON_GetObjectItemCaseSensitive(named, "switch_points");
    TEST_ASSERT_EQUAL_INT(cJSON_GetArraySize(npts), cJSON_GetArraySize(vpts));
    for (int k = 0; k < cJSON_GetArraySize(vpts); ++k)
    {
        TEST_ASSERT_EQUAL_DOUBLE(cJSON_GetArrayItem(npts, k)->valuedouble,
                                 cJSON_GetArrayItem(vpts, k)->valuedouble);
    }
    return named;
}

/* Run a table command that must succeed; its stdout. */
static const char *run_table(const char *const *args, cli_result_t *r)
{
    cli_run(r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r->status, r->err);
    return r->out;
}

static cJSON *run_json(const char *const *args, cli_result_t *r)
{
    cli_run(r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r->status, r->err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r->err_lines, r->err);
    cJSON *root = cJSON_Parse(r->out);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, "stdout is not one JSON object");
    return root;
}

/* ---- tests -------------------------------------------------------------------------------- */

/* The JSON contract on a nonlinear record (the paper's flap freeplay) and a linear one. Whether
 * the verdicts are right is measured, not asserted here: `aenl bench identify` runs the paper's
 * cases and the evaluation suite and prints the hits and the misses. */
static void test_cli_identify_flap_freeplay_json(void)
{
    const char *data = flap_record();
    const char *args[] = {"identify", data, "--method", "moments", "--json", NULL};
    static cli_result_t r;
    cJSON *root = run_json(args, &r);
    (void)check_contract(root, data, 3);
    cJSON_Delete(root);
}

static void test_cli_identify_linear_turbulence_json(void)
{
    const char *data = linear_record();
    const char *args[] = {"identify", data, "--method", "moments", "--json", NULL};
    static cli_result_t r;
    cJSON *root = run_json(args, &r);
    (void)check_contract(root, data, 3);
    cJSON_Delete(root);
}

/* Eval-suite case `index` of a 2-DOF section as a CSV without a time column, written once to
 * p (size bytes). */
static const char *eval_record(size_t index, const char *file, char *p, size_t size)
{
    (void)snprintf(p, size, "%s/%s", AENL_TEST_TMP_DIR, file);
    if (cli_exists(p))
    {
        return p;
    }
    aenl_eval_case_t c;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_eval_case_make(1, index, &c, &err), err.msg);
    FILE *f = fopen(p, "w");
    TEST_ASSERT_NOT_NULL(f);
    for (size_t k = 0; k < c.n_channels; ++k)
    {
        (void)fprintf(f, "%s%s", k > 0 ? "," : "", c.names[k]);
    }
    for (size_t n = 0; n < c.n_samples; ++n)
    {
        (void)fprintf(f, "\n");
        for (size_t k = 0; k < c.n_channels; ++k)
        {
            (void)fprintf(f, "%s%.17g", k > 0 ? "," : "", c.cols[k][n]);
        }
    }
    (void)fprintf(f, "\n");
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
    aenl_eval_case_free(&c);
    return p;
}

/* Eval-suite case 20: linear, a train of kicked releases, no noise. Unscreened, its kicks make
 * both analyses see a law. */
static const char *kicked_record(void)
{
    static char path[512];
    return eval_record(20, "id_kicked.csv", path, sizeof(path));
}

static void test_cli_identify_kicked_decay_train(void)
{
    const char *data = kicked_record();
    static cli_result_t r;
    const char *table[] = {"identify", data, "--method", "moments", NULL};
    const char *out = run_table(table, &r);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\n  impulsive excitation: "), out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\nverdict: linear"), out);
    const char *json[] = {"identify", data, "--method", "moments", "--json", NULL};
    static cli_result_t rj; /* r still holds the table */
    cJSON *root = run_json(json, &rj);
    (void)check_contract(root, data, 2);
    /* the JSON's notes are the table's note lines, word for word, and the events are counted */
    const cJSON *notes = cJSON_GetObjectItemCaseSensitive(root, "notes");
    TEST_ASSERT_TRUE(cJSON_GetArraySize(notes) >= 1);
    const cJSON *note = NULL;
    cJSON_ArrayForEach(note, notes)
    {
        char line[1200];
        (void)snprintf(line, sizeof(line), "\n  %s\n", note->valuestring);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, line), note->valuestring);
    }
    const cJSON *imp = cJSON_GetObjectItemCaseSensitive(root, "impulses");
    TEST_ASSERT_TRUE(cJSON_IsNumber(imp) && imp->valuedouble >= 1.0);
    cJSON_Delete(root);
}

/* The table of identify on eval-suite case `index` (its record written to `file` once, path
 * in p). */
static const char *eval_table(size_t index, const char *file, char *p, size_t size, cli_result_t *r)
{
    const char *table[] = {"identify", eval_record(index, file, p, size), "--method", "moments",
                           NULL};
    return run_table(table, r);
}

/* Eval-suite case 115: 3-DOF section, plunge hysteresis, noise-free turbulence. Pitch shows a
 * law that the plunge's explains: the table says so, and the verdict is the plunge's loop. The
 * record is cleaner than the regression's noise floor, and the table says that too. */
static void test_cli_identify_echo_of_another_channel(void)
{
    static char path[512];
    static cli_result_t r;
    const char *out = eval_table(115, "id_echo.csv", path, sizeof(path), &r);
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(out, "\n  alpha: the law it shows is explained by that of h (its force reaches "
                    "alpha through the coupling); alpha taken as linear\n"),
        out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\nverdict: hysteresis in channel h"), out);
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(out, "\n  h: cleaner than the regression's noise floor (SNR 10); white noise of "
                    "std "),
        out);
}

/* Eval-suite case 1: a hardening pitch spring in a limit cycle (SNR 10), which the core
 * classifier calls linear in both channels. Unforced, a limit cycle is not linear; told that
 * the motion is forced (--forced), identify takes the oscillation for what forcing gives. */
static void test_cli_identify_limit_cycle_and_forced(void)
{
    static char path[512];
    static cli_result_t r;
    const char *out = eval_table(1, "id_lco.csv", path, sizeof(path), &r);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\n  limit cycle: "), out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\nverdict: polynomial"), out);
    /* one orbit does not tell the laws apart: the class counts a third, and the other
     * channel's polynomial weight takes a share of the verdict's confidence; the line gives
     * both factors */
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\n  one orbit does not tell "), out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, " = 0.333 for the class in alpha × "), out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, " for the channel)"), out);
    const char *forced[] = {"identify", path, "--forced", NULL};
    out = run_table(forced, &r);
    TEST_ASSERT_NULL_MESSAGE(strstr(out, "limit cycle"), out);
    TEST_ASSERT_NULL_MESSAGE(strstr(out, "one orbit"), out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\nverdict: linear"), out);
}

static void test_cli_identify_table_and_channel(void)
{
    const char *data = flap_record();
    static cli_result_t r;
    /* given bandwidth: no cross-validation, a fast run */
    const char *table[] = {"identify", data, "--bandwidth", "0.002", NULL};
    cli_run(&r, table);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.err_lines, r.err);
    static const char *const k_heads[] = {"channel", "class",  "confidence", "bandwidth",
                                          "lags",    "period", "noise",      "switching points"};
    for (size_t i = 0; i < sizeof(k_heads) / sizeof(k_heads[0]); ++i)
    {
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, k_heads[i]), r.out);
    }
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "\nh "), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "\nalpha "), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "\nbeta "), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "\nverdict: "), r.out);
    TEST_ASSERT_NULL_MESSAGE(strchr(r.out, '{'), "the table is not JSON");

    /* --channel: only that one, given bandwidth and no pre-filter accepted */
    const char *one[] = {"identify", data,     "--method",    "moments", "--channel",
                         "beta",     "--json", "--bandwidth", "0.002",   "--no-prefilter",
                         NULL};
    cJSON *root = run_json(one, &r);
    check_contract(root, data, 1);
    const cJSON *ch = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "channels"), 0);
    TEST_ASSERT_EQUAL_STRING("beta", cJSON_GetObjectItemCaseSensitive(ch, "name")->valuestring);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.002,
                              cJSON_GetObjectItemCaseSensitive(ch, "bandwidth")->valuedouble);
    cJSON_Delete(root);
}

static void test_cli_identify_plot(void)
{
    if (system("command -v gnuplot >/dev/null 2>&1") != 0) /* NOLINT(cert-env33-c) */
    {
        TEST_IGNORE_MESSAGE("gnuplot not installed");
    }
    const char *data = flap_record();
    static cli_result_t r;
    (void)system("rm -rf '" AENL_TEST_TMP_DIR "/id_figs'"); /* NOLINT(cert-env33-c) */
    const char *args[] = {"identify", data,     "--channel",   "beta", "--bandwidth",
                          "0.002",    "--plot", "id_figs/sub", NULL};
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    static const char *const k_kinds[] = {"timeseries", "moments", "restoring"};
    for (size_t i = 0; i < 3; ++i)
    {
        char path[700];
        (void)snprintf(path, sizeof(path), "%s/id_figs/sub/id_flap_beta_%s.png", AENL_TEST_TMP_DIR,
                       k_kinds[i]);
        FILE *f = fopen(path, "rb");
        TEST_ASSERT_NOT_NULL_MESSAGE(f, path);
        unsigned char magic[8] = {0};
        const size_t got = fread(magic, 1, sizeof(magic), f);
        (void)fclose(f);
        TEST_ASSERT_EQUAL_size_t(8, got);
        TEST_ASSERT_EQUAL_HEX8_MESSAGE(0x89, magic[0], path); /* PNG signature */
        TEST_ASSERT_EQUAL_HEX8_MESSAGE('P', magic[1], path);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, path + strlen(AENL_TEST_TMP_DIR) + 1u), r.out);
    }
    /* nothing but the three figures (no temporary left beside them) */
    TEST_ASSERT_EQUAL_INT(0, system("test $(ls -A '" AENL_TEST_TMP_DIR /* NOLINT(cert-env33-c) */
                                    "/id_figs/sub' | wc -l) -eq 3"));

    /* a bad record with --plot: exit 2 and the folder is not created */
    const char *bad = cli_file("id_bad_plot.csv", "t,x\n0,1\n1,2\n1,3\n");
    const char *bad_args[] = {"identify", bad, "--plot", "bad_out_figs", NULL};
    cli_run(&r, bad_args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
    TEST_ASSERT_TRUE(cli_no_file_like("bad_out"));
}

/* ---- bad input ---------------------------------------------------------------------------- */

/* --model: the example record of `aenl diagnose` (2-DOF airfoil in a limit cycle, pitch freeplay
 * delta 0.5 deg from alpha_f 0.2 deg, SNR 3) against the example linear baseline. The record
 * alone cannot tell the laws apart over one orbit; the model-based test names freeplay in
 * alpha with the gap's edges within 5 % of its width (their standard errors given) and keeps
 * the record alone's verdict in the table. */
static void test_cli_identify_with_model(void)
{
    /* the diagnosis end to end runs under the sanitizers in test_diagnose, and the command's
     * --model path in the linear test below */
    AENL_PLAIN_BUILD_ONLY("a diagnosis end to end: left to the plain build");
    char ini[600], base[600];
    (void)snprintf(ini, sizeof(ini), "%s/tools/examples/diagnose_truth_airfoil2dof.ini",
                   source_root());
    (void)snprintf(base, sizeof(base), "%s/tools/examples/diagnose_base_airfoil2dof.ini",
                   source_root());
    const char *data = simulate(ini, "id_model.csv");
    static cli_result_t r;
    const char *args[] = {"identify", data, "--model", base, "--json", NULL};
    cJSON *root = run_json(args, &r);
    const cJSON *named = check_contract(root, data, 2);
    TEST_ASSERT_NOT_NULL_MESSAGE(named, r.out);
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "verdict");
    TEST_ASSERT_EQUAL_STRING("freeplay", cJSON_GetObjectItemCaseSensitive(v, "class")->valuestring);
    TEST_ASSERT_EQUAL_STRING("alpha", cJSON_GetObjectItemCaseSensitive(v, "channel")->valuestring);
    const cJSON *pts = cJSON_GetObjectItemCaseSensitive(v, "switch_points");
    TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(pts));
    const double width = 0.5 * DEG;
    TEST_ASSERT_DOUBLE_WITHIN(0.05 * width, 0.2 * DEG, cJSON_GetArrayItem(pts, 0)->valuedouble);
    TEST_ASSERT_DOUBLE_WITHIN(0.05 * width, 0.7 * DEG, cJSON_GetArrayItem(pts, 1)->valuedouble);
    const cJSON *sd = cJSON_GetObjectItemCaseSensitive(named, "switch_point_std");
    for (int k = 0; k < 2; ++k)
    {
        const cJSON *e = cJSON_GetArrayItem(sd, k);
        TEST_ASSERT_TRUE(cJSON_IsNumber(e) && e->valuedouble > 0.0 && e->valuedouble < 0.1 * width);
    }
    /* the model-based test as the table says it: freeplay in pitch, no second effect, the gap
     * closed, decided by the model */
    TEST_ASSERT_TRUE(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(v, "by_model")));
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(root, "model");
    TEST_ASSERT_TRUE(cJSON_IsObject(m));
    TEST_ASSERT_EQUAL_STRING("freeplay",
                             cJSON_GetObjectItemCaseSensitive(m, "effect")->valuestring);
    TEST_ASSERT_EQUAL_STRING("pitch", cJSON_GetObjectItemCaseSensitive(m, "dof")->valuestring);
    TEST_ASSERT_TRUE(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(m, "effect2")));
    TEST_ASSERT_TRUE(cJSON_GetObjectItemCaseSensitive(m, "gap_after")->valuedouble <
                     cJSON_GetObjectItemCaseSensitive(m, "gap_before")->valuedouble);
    cJSON_Delete(root);
    /* the same diagnosis again, printed as a table */
    const char *table[] = {"identify", data, "--model", base, NULL};
    const char *out = run_table(table, &r);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\n  model-based test against "), out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, ": freeplay in pitch, gap "), out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\n  the record alone: "), out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\nverdict (model-based): freeplay in channel alpha"),
                                 out);
    TEST_ASSERT_NULL_MESSAGE(strstr(out, "one orbit does not tell"), out);
    /* one law: no second effect */
    TEST_ASSERT_NULL_MESSAGE(strstr(out, "and a second effect"), out);
}

/* --model on a linear record: a rap test of the 3-DOF section without any law (the conditions
 * of tools/examples/section3dof_raps_base.ini, 8 s, SNR 10) against its own model. The baseline
 * fits within its noise floor and its summaries agree, so the model-based verdict is linear,
 * whatever the record alone says. */
static void test_cli_identify_with_model_linear(void)
{
    static const char rig[] = "[model]\ntype = section3dof\nvelocity = 12\n\n"
                              "[excitation]\ntype = kicks\ndof = pitch\nevery = 1.5\n"
                              "rate_deg = 20\nrate_max_deg = 40\nseed = 3\n\n"
                              "[run]\nduration = 8\ndt = 0.002\n";
    char truth[1024];
    (void)snprintf(truth, sizeof(truth), "%s\n[noise]\nsnr = 10\nseed = 5\n", rig);
    const char *base = cli_file("id_lin_base.ini", rig);
    const char *data = simulate(cli_file("id_lin_truth.ini", truth), "id_lin.csv");
    static cli_result_t r;
    const char *args[] = {"identify", data, "--model", base, "--json", NULL};
    cJSON *root = run_json(args, &r);
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "verdict");
    TEST_ASSERT_EQUAL_STRING_MESSAGE(
        "linear", cJSON_GetObjectItemCaseSensitive(v, "class")->valuestring, r.out);
    cJSON_Delete(root);
    if (!AENL_TEST_IS_SANITIZED) /* the same diagnosis again, printed as a table */
    {
        const char *table[] = {"identify", data, "--model", base, NULL};
        const char *out = run_table(table, &r);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "and its summaries agree (p "), out);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, "\nverdict (model-based): linear"), out);
    }
}

/* --model on two freeplays at once (tools/examples/section3dof_two_freeplays.ini: pitch gap
 * -0.1..0.1 deg, flap gap -1..1 deg, noise-free): the test names the flap's, finds the pitch's
 * with the flap's in the model, and refits each with the other in place. Both channels are
 * freeplay with the gaps' edges near the truth (flap within 2 %, pitch within 20 % of its
 * width: the pitch gap is a tenth of the flap's), plunge linear. */
static void test_cli_identify_with_model_two_freeplays(void)
{
    /* Four diagnoses end to end take minutes under the sanitizers; the diagnosis runs there in
     * test_cli_diagnose and test_diagnose, and the command's --model path in the linear test
     * above; this one runs in the strict build. */
    AENL_PLAIN_BUILD_ONLY(
        "four diagnoses: left to the strict build (minutes under the sanitizers)");
    char ini[600], base[600];
    (void)snprintf(ini, sizeof(ini), "%s/tools/examples/section3dof_two_freeplays.ini",
                   source_root());
    (void)snprintf(base, sizeof(base), "%s/tools/examples/section3dof_two_freeplays_base.ini",
                   source_root());
    const char *data = simulate(ini, "id_two_freeplays.csv");
    static cli_result_t r;
    const char *args[] = {"identify", data, "--model", base, "--json", NULL};
    cJSON *root = run_json(args, &r);
    TEST_ASSERT_NOT_NULL_MESSAGE(check_contract(root, data, 3), r.out);
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "verdict");
    TEST_ASSERT_EQUAL_STRING("freeplay", cJSON_GetObjectItemCaseSensitive(v, "class")->valuestring);
    const struct
    {
        const char *name, *cls;
        double lo, hi, tol; /* truth's edges (rad) and the tolerance, fraction of the width */
    } want[] = {{"h", "linear", 0.0, 0.0, 0.0},
                {"alpha", "freeplay", -0.1 * DEG, 0.1 * DEG, 0.2},
                {"beta", "freeplay", -1.0 * DEG, 1.0 * DEG, 0.02}};
    const cJSON *chs = cJSON_GetObjectItemCaseSensitive(root, "channels");
    TEST_ASSERT_EQUAL_INT(3, cJSON_GetArraySize(chs));
    for (int k = 0; k < 3; ++k)
    {
        const cJSON *ch = cJSON_GetArrayItem(chs, k);
        TEST_ASSERT_EQUAL_STRING(want[k].name,
                                 cJSON_GetObjectItemCaseSensitive(ch, "name")->valuestring);
        TEST_ASSERT_EQUAL_STRING_MESSAGE(
            want[k].cls, cJSON_GetObjectItemCaseSensitive(ch, "class")->valuestring, r.out);
        if (want[k].hi > want[k].lo)
        {
            const cJSON *pts = cJSON_GetObjectItemCaseSensitive(ch, "switch_points");
            const double w = want[k].hi - want[k].lo;
            TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(pts));
            TEST_ASSERT_DOUBLE_WITHIN(want[k].tol * w, want[k].lo,
                                      cJSON_GetArrayItem(pts, 0)->valuedouble);
            TEST_ASSERT_DOUBLE_WITHIN(want[k].tol * w, want[k].hi,
                                      cJSON_GetArrayItem(pts, 1)->valuedouble);
        }
    }
    cJSON_Delete(root);
}

typedef struct
{
    const char *what;
    const char *args[12];
    const char *needle;
} bad_case_t;

static void run_bad(const bad_case_t *c)
{
    static cli_result_t r;
    static char msg[sizeof(r.err) + 512];
    (void)system("rm -rf '" AENL_TEST_TMP_DIR "'/bad_out*"); /* NOLINT(cert-env33-c) */
    cli_run(&r, c->args);
    (void)snprintf(msg, sizeof(msg), "%s: exit %d, %d stderr line(s), %zu stdout bytes; %s",
                   c->what, r.status, r.err_lines, r.n_out, r.err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, r.err_lines, msg);
    TEST_ASSERT_EQUAL_size_t_MESSAGE(0, r.n_out, msg);
    TEST_ASSERT_TRUE_MESSAGE(strncmp(r.err, "aenl identify: ", 15) == 0, msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, c->needle), msg);
    TEST_ASSERT_TRUE_MESSAGE(cli_no_file_like("bad_out"), msg);
}

/* t,a,b: n rows of two oscillations; row `row` replaced by `edit` when not NULL. */
static const char *small_csv(const char *name, size_t n, size_t row, const char *edit)
{
    static char text[1 << 16];
    size_t pos = (size_t)snprintf(text, sizeof(text), "t,a,b\n");
    for (size_t i = 0; i < n && pos + 100 < sizeof(text); ++i)
    {
        if (edit != NULL && i == row)
        {
            pos += (size_t)snprintf(text + pos, sizeof(text) - pos, "%s\n", edit);
            continue;
        }
        pos += (size_t)snprintf(text + pos, sizeof(text) - pos, "%zu,%.6f,%.6f\n", i,
                                sin(0.3 * (double)i), cos(0.17 * (double)i));
    }
    return put_file(name, text);
}

static void test_cli_identify_bad_input(void)
{
    const char *good = small_csv("id_good.csv", 400, 0, NULL);
    static char constant[1 << 14];
    size_t pos = (size_t)snprintf(constant, sizeof(constant), "t,a,b\n");
    for (int i = 0; i < 300; ++i)
    {
        pos += (size_t)snprintf(constant + pos, sizeof(constant) - pos, "%d,0.25,%g\n", i,
                                sin(0.3 * i));
    }
    const char *flat = put_file("id_const.csv", constant);
    /* a valid model whose channels (alpha, xi) the record (a, b) does not have */
    const char *model_ini =
        put_file("id_model_base.ini", "[model]\ntype = airfoil2dof\nustar = 4\n\n[initial]\n"
                                      "alpha_deg = 1\n\n[run]\nduration = 100\ndt = 1\n");
    const bad_case_t cases[] = {
        {"missing file", {"identify", "/nonexistent/x.csv", NULL}, "/nonexistent/x.csv"},
        {"empty", {"identify", put_file("id_empty.csv", ""), NULL}, "id_empty.csv: empty file"},
        {"header only", {"identify", put_file("id_hdr.csv", "t,a,b\n"), NULL}, "no data rows"},
        {"time only",
         {"identify", put_file("id_tonly.csv", "t\n0\n1\n"), NULL},
         "id_tonly.csv: no data column"},
        {"non-numeric",
         {"identify", small_csv("id_nonnum.csv", 400, 9, "9,x1,0"), NULL},
         "id_nonnum.csv:11:2 (a): not a number"},
        {"Inf cell",
         {"identify", small_csv("id_inf.csv", 400, 9, "9,inf,0"), NULL},
         "id_inf.csv:11:2 (a): infinite"},
        {"ragged row",
         {"identify", small_csv("id_ragged.csv", 400, 9, "9,1"), NULL},
         "id_ragged.csv:11"},
        {"time not increasing",
         {"identify", small_csv("id_mono.csv", 400, 20, "5,0.1,0.2"), NULL},
         "id_mono.csv: column 't', data row 21: time 5 does not increase"},
        {"missing time",
         {"identify", small_csv("id_nant.csv", 400, 20, "nan,0.1,0.2"), NULL},
         "id_nant.csv: column 't', data row 21: missing time"},
        {"huge value",
         {"identify", small_csv("id_huge.csv", 400, 30, "30,1e300,0.2"), NULL},
         "id_huge.csv: column 'a', data row 31: value 1e+300 is too large"},
        {"all missing",
         {"identify", put_file("id_nan.csv", "t,a,b\n0,nan,1\n1,nan,2\n2,,3\n"), NULL},
         "id_nan.csv, channel a: no finite sample"},
        {"constant", {"identify", flat, NULL}, "id_const.csv, channel a: constant signal"},
        {"unknown channel",
         {"identify", good, "--channel", "nope", NULL},
         "id_good.csv: no channel 'nope' (channels: a, b)"},
        {"time as channel", {"identify", good, "--channel", "t", NULL}, "no channel 't'"},
        {"standard input, moments", {"identify", "-", "--method", "moments", NULL}, "not '-'"},
        {"no file", {"identify", "--json", NULL}, "no data file"},
        {"two files", {"identify", good, good, NULL}, "one data file only"},
        {"unknown option", {"identify", good, "--bogus", NULL}, "unknown option --bogus"},
        {"missing value", {"identify", good, "--channel", NULL}, "--channel needs a value"},
        {"bad bandwidth", {"identify", good, "--bandwidth", "-1", NULL}, "--bandwidth"},
        {"bandwidth not a number",
         {"identify", good, "--bandwidth", "abc", NULL},
         "--bandwidth: 'abc' is not a finite number"},
        {"model and channel",
         {"identify", good, "--model", "m.ini", "--channel", "a", NULL},
         "does not go with --channel"},
        {"missing model", {"identify", good, "--model", "/nonexistent/m.ini", NULL}, "m.ini"},
        {"model without its channels",
         {"identify", small_csv("id_ab.csv", 1200, 0, NULL), "--model", model_ini, NULL},
         "no column 'alpha'"},
        {"unwritable plot folder",
         {"identify", good, "--plot", "/proc/nope/figs", NULL},
         "/proc/nope"},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i)
    {
        if (strcmp(cases[i].what, "unwritable plot folder") == 0 &&
            system("command -v gnuplot >/dev/null 2>&1") != 0) /* NOLINT(cert-env33-c) */
        {
            continue; /* without gnuplot, --plot fails earlier (tested by that message) */
        }
        run_bad(&cases[i]);
    }
}

/* Part 1 or 2 (argument; none: both), so that ctest runs the two halves side by side: the
 * model-based tests take most of the time, the two-freeplay one about half of it. */
int main(int argc, char **argv)
{
    const long part = argc > 1 ? strtol(argv[1], NULL, 10) : 0;
    UNITY_BEGIN();
    if (part != 2)
    {
        RUN_TEST(test_cli_identify_flap_freeplay_json);
        RUN_TEST(test_cli_identify_linear_turbulence_json);
        RUN_TEST(test_cli_identify_kicked_decay_train);
        RUN_TEST(test_cli_identify_limit_cycle_and_forced);
        RUN_TEST(test_cli_identify_echo_of_another_channel);
        RUN_TEST(test_cli_identify_table_and_channel);
        RUN_TEST(test_cli_identify_plot);
        RUN_TEST(test_cli_identify_with_model_two_freeplays);
    }
    if (part != 1)
    {
        RUN_TEST(test_cli_identify_with_model);
        RUN_TEST(test_cli_identify_with_model_linear);
        RUN_TEST(test_cli_identify_bad_input);
    }
    return UNITY_END();
}
