/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_demo.c
 * @brief `aenl demo`: the worked examples end to end, with figures, into one output folder.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_bandwidth.h"
#include "aenl_tools/aenl_curves.h"
#include "aenl_tools/aenl_identify.h"
#include "aenl_tools/aenl_nltest.h"
#include "aenl_tools/aenl_plot.h"
#include "aenl_tools/aenl_sim.h"

static const char *const k_cmd = "demo";

static int make_dir(const char *path)
{
    char buf[1024];
    const size_t len = strlen(path);
    if (len >= sizeof(buf))
    {
        return -1;
    }
    memcpy(buf, path, len + 1u);
    for (char *p = buf + 1; *p; ++p)
    {
        if (*p == '/')
        {
            *p = '\0';
            if (mkdir(buf, 0777) != 0 && errno != EEXIST)
            {
                return -1;
            }
            *p = '/';
        }
    }
    if (mkdir(buf, 0777) != 0 && errno != EEXIST)
    {
        return -1;
    }
    return 0;
}

static int file_exists(const char *p)
{
    struct stat sb;
    return stat(p, &sb) == 0 && S_ISREG(sb.st_mode);
}

/* Curves of one channel (n samples): CSV + figure in the output folder. */
/* The path of an example model shipped with aenl (share/aenl/examples); 0, or -1 after the error
 * message. */
static int example_path(const char *name, char *buf, size_t n)
{
    char rel[256];
    aenl_err_t err;
    aenl_err_clear(&err);
    if (snprintf(rel, sizeof(rel), "examples/%s", name) >= (int)sizeof(rel) ||
        aenl_share_path(rel, buf, n, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg[0] != '\0' ? err.msg : "example name too long");
        return -1;
    }
    return 0;
}

static int curves_of_array(const double *x, size_t n, const char *source, const char *channel,
                           const char *outdir, const char *stem, const char *label)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_curves_opts_t o;
    aenl_curves_opts_default(&o);
    aenl_curves_t c;
    aenl_status_t st = aenl_curves_compute(x, n, &o, &c, &err);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s (%s): %s", source, channel, err.msg);
        return -1;
    }
    char csv[1200], png[1200], title[600];
    if (snprintf(csv, sizeof(csv), "%s/%s_moments.csv", outdir, stem) >= (int)sizeof(csv) ||
        snprintf(png, sizeof(png), "%s/%s_moments.png", outdir, stem) >= (int)sizeof(png))
    {
        aenl_cli_error(k_cmd, "%s: output path too long", outdir);
        return -1;
    }
    (void)snprintf(title, sizeof(title), "%s: conditional mean and variance (h = %.3g by %s)",
                   label, c.bandwidth, c.bw_method < 0 ? "hand" : aenl_bw_method_str(c.bw_method));
    st = aenl_curves_write_csv(&c, AENL_DIR_ALL, source, channel, csv, &err);
    if (st == AENL_OK && aenl_plot_available())
    {
        const aenl_plot_var_t vars[] = {
            {"in", csv}, {"lags", "1 10 30"}, {"title", title}, {"xlabel", channel}};
        st = aenl_plot_run("moments", vars, 4, png, &err);
    }
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        aenl_curves_free(&c);
        return -1;
    }
    printf("    curves of %-8s bandwidth %.4g (%s) -> %s%s%s\n", channel, c.bandwidth,
           c.bw_method < 0 ? "given" : aenl_bw_method_str(c.bw_method), csv,
           aenl_plot_available() ? ", " : "", aenl_plot_available() ? png : "");
    aenl_curves_free(&c);
    return 0;
}

/* Curves of one channel of a measured record. */
static int curves_of_file(const char *data, const char *channel, const char *outdir,
                          const char *stem, const char *label)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_table_t t;
    if (aenl_table_read(data, &t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return -1;
    }
    const long col = aenl_cli_pick_channel(k_cmd, &t, data, channel);
    if (col < 0)
    {
        aenl_table_free(&t);
        return -1;
    }
    const int rc = curves_of_array(aenl_table_col(&t, (size_t)col), t.n_rows, data, channel, outdir,
                                   stem, label);
    aenl_table_free(&t);
    return rc;
}

/* One of the paper's simulated cases: simulate the example INI, write the record and its time
 * series figure, then the curves of the channel that carries the nonlinearity. */

/* Print a verdict and its switching points next to the truth; 1 when class and channel match. */
static int print_verdict(const aenl_identify_result_t *r, const char *truth_class,
                         const char *truth_channel)
{
    const char *got_class = aenl_class_name(r->verdict_class);
    const char *got_channel = r->verdict >= 0 ? r->ch[r->verdict].name : "-";
    const int hit = strcmp(got_class, truth_class) == 0 && strcmp(got_channel, truth_channel) == 0;
    printf("%s in %s", got_class, got_channel);
    if (r->verdict >= 0)
    {
        const aenl_classifier_result_t *res = &r->ch[r->verdict].res;
        printf(" (confidence %.2f", r->verdict_confidence);
        for (uint8_t k = 0; k < res->n_switch; ++k)
        {
            printf("%s%.5g", k == 0 ? "; switching points " : ", ", (double)res->switch_points[k]);
        }
        printf(")");
    }
    printf("; truth: %s in %s -> %s\n", truth_class, truth_channel, hit ? "match" : "MISS");
    return hit;
}

/* The record alone by identify's default method, the likelihood-based test, on every channel
 * of the CSV but its time column: the verdict printed next to the truth. Returns 1 on a match,
 * 0 on a miss, -1 on an error. */
static int test_verdict(const char *csv, const char *truth_class, const char *truth_channel)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_table_t t;
    if (aenl_table_read(csv, &t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return -1;
    }
    const double *chan[AENL_NLT_MAX_CH];
    const char *names[AENL_NLT_MAX_CH];
    size_t nz = 0;
    if (aenl_cli_record_channels(k_cmd, &t, csv, NULL, 0, -1, AENL_NLT_MAX_CH, chan, names, &nz) !=
        0)
    {
        aenl_table_free(&t);
        return -1;
    }
    aenl_nlt_opts_t opts;
    aenl_nlt_opts_default(&opts);
    aenl_nlt_result_t res;
    const aenl_status_t st = aenl_nlt_run_columns(chan, t.n_rows, nz, &opts, &res, &err);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s: %s", csv, err.msg);
        aenl_table_free(&t);
        return -1;
    }
    const char *got_class = aenl_nlt_class_name(res.verdict_class, res.undetermined);
    const char *got_channel = res.verdict >= 0 ? names[res.verdict] : "-";
    const int hit = strcmp(got_class, truth_class) == 0 && strcmp(got_channel, truth_channel) == 0;
    printf("    identified (aenl identify %s): %s in %s (confidence %.2f", csv, got_class,
           got_channel, res.confidence);
    if (res.verdict >= 0)
    {
        const aenl_nlt_channel_t *c = &res.ch[res.verdict];
        for (size_t k = 0; k < c->n_points; ++k)
        {
            printf("%s%.5g", k == 0 ? "; switching points " : ", ", c->points[k]);
        }
    }
    printf("); truth: %s in %s -> %s\n", truth_class, truth_channel, hit ? "match" : "MISS");
    aenl_table_free(&t);
    return hit;
}

/* "per channel:" and every channel's class (with its switching points). */
static void print_channels(const aenl_identify_result_t *r, const char *indent)
{
    printf("%sper channel:", indent);
    for (size_t k = 0; k < r->n_channels; ++k)
    {
        const aenl_classifier_result_t *res = &r->ch[k].res;
        printf("%s %s %s", k == 0 ? "" : ",", r->ch[k].name, aenl_class_name(res->cls));
        for (uint8_t i = 0; i < res->n_switch; ++i)
        {
            printf("%s%.5g%s", i == 0 ? " [" : ", ", (double)res->switch_points[i],
                   i + 1 == res->n_switch ? "]" : "");
        }
    }
    printf("\n");
}

/**
 * The record's identification r with its baseline model (what `aenl identify CSV --model BASE`
 * prints): the model-based test's verdict next to the truth. r is updated in place. Returns 1 on
 * a match, 0 on a miss, -1 on an error.
 */
static int model_verdict(aenl_identify_result_t *r, const char *csv, const char *base_name,
                         const char *truth_class, const char *truth_channel)
{
    char base_ini[1200];
    aenl_err_t err;
    aenl_err_clear(&err);
    if (example_path(base_name, base_ini, sizeof(base_ini)) != 0)
    {
        return -1;
    }
    aenl_sim_model_t base;
    aenl_sim_run_t run;
    aenl_table_t t;
    memset(&t, 0, sizeof(t));
    aenl_status_t st = aenl_sim_load_ini(base_ini, &base, &run, &err);
    if (st == AENL_OK)
    {
        st = aenl_table_read(csv, &t, &err);
    }
    if (st == AENL_OK)
    {
        st = aenl_identify_model_test(r, &t, &base, &run, NULL, NULL, &err);
    }
    aenl_table_free(&t);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s --model %s: %s", csv, base_ini, err.msg);
        return -1;
    }
    printf("    with the baseline model (aenl identify %s --model %s):\n      ", csv, base_ini);
    return print_verdict(r, truth_class, truth_channel);
}

/**
 * Identify a record (all channels) and print the verdicts next to the truth: the test's (the
 * record alone by identify's default) and the conditional moments'; with base_name (an
 * INI under tools/examples), also the model-based verdict on the moments' identification
 * (*model_hit 1 on a match); with gnuplot, run `aenl identify --plot` for the paper-style
 * figures. Returns 1 when the test's verdict matches the truth (class and channel), 0 when not,
 * -1 on an error.
 */
static int identify_case(const char *csv, const char *outdir, const char *stem,
                         const char *truth_class, const char *truth_channel, const char *base_name,
                         int *model_hit)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_identify_source_t src;
    aenl_identify_csv_t ctx;
    aenl_identify_result_t r;
    aenl_status_t st = aenl_identify_csv_source(&src, &ctx, csv, NULL, &err);
    if (st == AENL_OK)
    {
        aenl_identify_opts_t o;
        aenl_identify_opts_default(&o);
        st = aenl_identify_run(&src, &o, &r, &err);
    }
    if (st != AENL_OK)
    {
        aenl_identify_csv_free(&ctx); /* safe on the zeroed context of a failed open */
        aenl_cli_error(k_cmd, "%s", err.msg);
        return -1;
    }
    const int hit = test_verdict(csv, truth_class, truth_channel);
    if (hit < 0)
    {
        aenl_identify_free(&r);
        aenl_identify_csv_free(&ctx);
        return -1;
    }
    printf("    conditional moments (--method moments): ");
    (void)print_verdict(&r, truth_class, truth_channel);
    print_channels(&r, "    ");
    const int mh =
        base_name != NULL ? model_verdict(&r, csv, base_name, truth_class, truth_channel) : 0;
    if (mh >= 0 && base_name != NULL)
    {
        print_channels(&r, "      ");
    }
    aenl_identify_free(&r);
    aenl_identify_csv_free(&ctx); /* the channel names live in the source */
    if (mh < 0)
    {
        return -1;
    }
    *model_hit += mh;
    if (aenl_plot_available())
    {
        char dir[1200];
        if (snprintf(dir, sizeof(dir), "%s/%s_identify", outdir, stem) >= (int)sizeof(dir))
        {
            aenl_cli_error(k_cmd, "%s: output path too long", outdir);
            return -1;
        }
        printf(
            "    the moments' figures and table (aenl identify %s --method moments --plot %s):\n",
            csv, dir);
        (void)fflush(stdout);
        aenl_identify_opts_t opts;
        aenl_identify_opts_default(&opts);
        if (aenl_identify_by_moments(csv, NULL, &opts, NULL, 0, dir) != AENL_EXIT_OK)
        {
            return -1;
        }
    }
    return hit;
}

static int paper_case(const char *ini_name, const char *base_name, const char *channel,
                      const char *outdir, const char *stem, const char *label,
                      const char *truth_class, int *hits, int *model_hits)
{
    char ini[1200], csv[1200], png[1200];
    if (example_path(ini_name, ini, sizeof(ini)) != 0)
    {
        return -1;
    }
    if (snprintf(csv, sizeof(csv), "%s/%s.csv", outdir, stem) >= (int)sizeof(csv) ||
        snprintf(png, sizeof(png), "%s/%s_timeseries.png", outdir, stem) >= (int)sizeof(png))
    {
        aenl_cli_error(k_cmd, "%s: output path too long", outdir);
        return -1;
    }
    printf("  %s  (%s)\n", label, ini);
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_model_t model;
    aenl_sim_run_t run;
    aenl_sim_result_t res;
    memset(&res, 0, sizeof(res));
    aenl_status_t st = aenl_sim_load_ini(ini, &model, &run, &err);
    if (st == AENL_OK)
    {
        st = aenl_sim_simulate(&model, &run, &res, &err);
    }
    if (st == AENL_OK)
    {
        st = aenl_sim_result_write_csv(&res, csv, &err);
    }
    if (st == AENL_OK && aenl_plot_available())
    {
        const aenl_plot_var_t vars[] = {{"in", csv}, {"title", label}};
        st = aenl_plot_run("timeseries", vars, 2, png, &err);
    }
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        aenl_sim_result_free(&res);
        return -1;
    }
    printf("    simulated %zu samples (%lu steps, %lu events) -> %s%s%s\n", res.n_samples,
           res.info.n_steps, res.info.n_events, csv, aenl_plot_available() ? ", " : "",
           aenl_plot_available() ? png : "");
    int rc = -1;
    for (size_t c = 0; c < res.n_channels; ++c)
    {
        if (strcmp(res.names[c + 1u], channel) == 0)
        {
            rc = curves_of_array(res.y + c * res.n_samples, res.n_samples, ini, channel, outdir,
                                 stem, label);
        }
    }
    aenl_sim_result_free(&res);
    if (rc == 0 && truth_class != NULL)
    {
        const int hit =
            identify_case(csv, outdir, stem, truth_class, channel, base_name, model_hits);
        rc = hit < 0 ? -1 : 0;
        *hits += hit > 0;
    }
    return rc;
}

int aenl_cmd_demo(int argc, char **argv)
{
    const char *outdir = "out/demo";
    const char *datadir = getenv("AENL_DATA_DIR");
    for (int i = 1; i < argc; ++i)
    {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
        {
            printf("usage: aenl demo [--out DIR] [--data DIR]\n\n"
                   "Runs the worked examples end to end and writes CSVs and figures to DIR\n"
                   "(default out/demo). --data (or $AENL_DATA_DIR) is the folder of measured\n"
                   "records that holds the Bristol flutter rig data set; without it the\n"
                   "real-data example is skipped.\n");
            return AENL_EXIT_OK;
        }
        if (strcmp(argv[i], "--out") == 0)
        {
            if ((outdir = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(argv[i], "--data") == 0)
        {
            if ((datadir = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else
        {
            aenl_cli_error(k_cmd, "unknown argument %s (aenl demo --help)", argv[i]);
            return AENL_EXIT_USAGE;
        }
    }
    if (datadir != NULL)
    {
        struct stat sb; /* a folder the user named must exist; the default one may be absent */
        if (stat(datadir, &sb) != 0 || !S_ISDIR(sb.st_mode))
        {
            aenl_cli_error(k_cmd, "--data %s: not a folder", datadir);
            return AENL_EXIT_USAGE;
        }
    }
    if (make_dir(outdir) != 0)
    {
        aenl_cli_error(k_cmd, "cannot create the output folder %s: %s", outdir, strerror(errno));
        return AENL_EXIT_USAGE;
    }
    if (!aenl_plot_available())
    {
        printf("(gnuplot not found: CSVs only; apt-get install gnuplot-nox for the figures)\n");
    }
    int failures = 0;

    int hits = 0, model_hits = 0;
    printf("The paper's three cases, simulated (SNR 3 measurement noise), then identified:\n");
    failures +=
        paper_case("paper_polynomial_pitch.ini", "paper_polynomial_pitch_base.ini", "alpha", outdir,
                   "paper_polynomial_pitch", "Polynomial pitch stiffness (paper Figs. 2, 5, 6)",
                   "polynomial", &hits, &model_hits) != 0;
    failures += paper_case("paper_hysteresis_pitch.ini", "paper_hysteresis_pitch_base.ini", "alpha",
                           outdir, "paper_hysteresis_pitch",
                           "Hysteresis in pitch, delta 1 deg, alpha_f 0 (Figs. 3, 7, 8)",
                           "hysteresis", &hits, &model_hits) != 0;
    failures +=
        paper_case("paper_flap_freeplay.ini", "paper_flap_freeplay_base.ini", "beta", outdir,
                   "paper_flap_freeplay", "Flap freeplay, gap -1..1 deg (Figs. 4, 9)", "freeplay",
                   &hits, &model_hits) != 0;
    printf("Two freeplays at once (3-DOF, pitch and flap):\n");
    failures += paper_case("section3dof_two_freeplays.ini", NULL, "beta", outdir, "two_freeplays",
                           "Pitch and flap freeplay, 3-DOF", NULL, &hits, &model_hits) != 0;
    {
        char csv2[1200];
        if (snprintf(csv2, sizeof(csv2), "%s/two_freeplays.csv", outdir) < (int)sizeof(csv2))
        {
            int unused = 0;
            const int hit = identify_case(csv2, outdir, "two_freeplays", "freeplay", "beta",
                                          "section3dof_two_freeplays_base.ini", &unused);
            failures += hit < 0;
        }
    }
    printf("Paper cases identified correctly: %d of 3 from the record alone (the test), %d of 3 "
           "with the baseline model\n",
           hits, model_hits);

    printf("Measured: Bristol pitch-heave flutter rig, LCO at 25.0 m/s (polynomial pitch "
           "stiffness)\n");
    char rec[1200];
    const int rec_len = datadir == NULL
                            ? -1
                            : snprintf(rec, sizeof(rec),
                                       "%s/bristol_flutter_rig_pitch_heave/lco_sweep_17092018/"
                                       "17092018_CBC_V250_TowardsHB.csv",
                                       datadir);
    if (rec_len > 0 && rec_len < (int)sizeof(rec) && file_exists(rec))
    {
        printf("  %s\n", rec);
        failures += curves_of_file(rec, "pitch_encoder_rad", outdir, "bristol_V250_pitch",
                                   "Bristol rig pitch, 25 m/s LCO") != 0;
        failures += curves_of_file(rec, "heave_raw", outdir, "bristol_V250_heave",
                                   "Bristol rig heave, 25 m/s LCO") != 0;
    }
    else if (datadir == NULL)
    {
        printf("  (skipped: no folder of measured records given; --data DIR or $AENL_DATA_DIR "
               "names it)\n");
    }
    else
    {
        printf("  (skipped: %s not found)\n", rec_len > 0 ? rec : datadir);
    }
    printf("%s: %s\n", failures ? "demo finished with errors" : "demo done", outdir);
    return failures ? AENL_EXIT_FAIL : AENL_EXIT_OK;
}
