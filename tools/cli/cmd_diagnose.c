/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_diagnose.c
 * @brief `aenl diagnose --measured DATA.csv --model BASE.ini [--out DIR] [--json]`: where the
 *        baseline model and the measurement disagree, the missing effect, the updated model and
 *        the gap before and after (docs/diagnose.md).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_diagnose.h"
#include "aenl_tools/aenl_parallel.h"
#include "aenl_tools/aenl_plot.h"
#include "aenl_tools/aenl_sim.h"

static const char *const k_cmd = "diagnose";

static void help(void)
{
    printf(
        "usage: aenl diagnose --measured DATA.csv --model BASE.ini [--out DIR] [--json]\n"
        "                     [--replicates N] [--penalty P] [--seed S] [--refine K]\n"
        "                     [--max-evals M] [--summary-records N] [--jobs N]\n"
        "                     [--no-plots] [-v]\n\n"
        "Simulates the baseline model BASE.ini under the conditions of the record (its [run] dt\n"
        "must be the record's sample step; the record's length sets the duration), compares\n"
        "per-channel signatures (amplitude quantiles and envelope, conditional mean and std\n"
        "curves, spectrum) against the measured ones and against the noise floor (replicates\n"
        "with other seeds), calibrates each candidate effect (freeplay, hysteresis, cubic and\n"
        "quintic polynomial, preload; every DOF whose baseline law is linear) by simulation,\n"
        "and names the one with the least penalised gap, or none.\n"
        "DATA.csv: a time column (t, time, tau or timestamp) and the model's channels by name\n"
        "(airfoil2dof: alpha, xi; section3dof: h, alpha, beta), in the model's units.\n"
        "A free decay's release (no turbulence, no kicks) may be left out of BASE.ini: with no\n"
        "[initial] state, or with [initial] estimate = true, it is fitted to the record's first\n"
        "samples for every model compared and reported with standard errors.\n\n"
        "--out DIR        write DIR/updated.ini (runs with `aenl simulate` as is), report.txt,\n"
        "                 gaps.csv, candidates.csv, curves_<ch>.csv, spectrum_<ch>.csv,\n"
        "                 timeseries.csv and, with gnuplot, the figures diagnose_*.png\n"
        "--json           print {\"disagreement\", \"missing_effect\", \"gap_before\", "
        "\"gap_after\",\n"
        "                 \"updated_model\"} instead of the report (updated_model: the INI path\n"
        "                 with --out, else null), and \"initial_state\" when the release was "
        "fitted\n"
        "--replicates N   runs per noise-floor estimate besides the main one (default 3)\n"
        "--penalty P      choice penalty per parameter in chi-square units (default 2, AIC)\n"
        "--seed S         seed of the simulated measurement noise (default 1)\n"
        "--refine K       candidates refined by Nelder-Mead after the grid (default 4)\n"
        "--max-evals M    Nelder-Mead simulations per refined candidate (default 40)\n"
        "--summary-records N  records simulated to refit the named effect's parameters to the\n"
        "                 record's summaries (amplitude, frequency, kurtosis, harmonics of every\n"
        "                 channel, efficiently weighted) and give their standard errors\n"
        "                 (params_sd in JSON); when no effect is named because the baseline\n"
        "                 fits within twice its floor, records of the baseline that the\n"
        "                 record's summaries are ranked among (the report says whether they\n"
        "                 agree); 32..4096, default 64; 0: neither (keep the gap's fit)\n"
        "--jobs N         simulations run at once, on N threads, 1..64 (default: the\n"
        "                 processors online); the answer is the same for any N\n"
        "--time COL       the record's time column is COL (default: the one named t, time,\n"
        "                 tau or timestamp, alone or with a unit)\n"
        "--no-plots       no figures\n"
        "-v               progress on stderr\n");
}

/* The figures: signatures per channel, spectra, time histories, gaps. */
static aenl_status_t make_figures(const aenl_diagnose_result_t *r, const char *dir, aenl_err_t *err)
{
    char in[4096], out[4096], title[256];
    aenl_status_t st = AENL_OK;
    for (size_t c = 0; c < r->n_channels && st == AENL_OK; ++c)
    {
        (void)snprintf(in, sizeof(in), "%s/curves_%s.csv", dir, r->names[c]);
        (void)snprintf(out, sizeof(out), "%s/diagnose_curves_%s.png", dir, r->names[c]);
        (void)snprintf(title, sizeof(title), "%s: measured, baseline, updated (lag %u)",
                       r->names[c], (unsigned)r->chan[c].lags[1]);
        const aenl_plot_var_t v1[] = {{"in", in}, {"title", title}, {"xlabel", r->names[c]}};
        st = aenl_plot_run("diagnose_curves", v1, 3, out, err);
        if (st != AENL_OK)
        {
            break;
        }
        (void)snprintf(in, sizeof(in), "%s/spectrum_%s.csv", dir, r->names[c]);
        (void)snprintf(out, sizeof(out), "%s/diagnose_spectrum_%s.png", dir, r->names[c]);
        (void)snprintf(title, sizeof(title), "%s: spectrum", r->names[c]);
        const aenl_plot_var_t v2[] = {{"in", in}, {"title", title}};
        st = aenl_plot_run("diagnose_spectrum", v2, 2, out, err);
    }
    if (st == AENL_OK)
    {
        (void)snprintf(in, sizeof(in), "%s/timeseries.csv", dir);
        (void)snprintf(out, sizeof(out), "%s/diagnose_timeseries.png", dir);
        const aenl_plot_var_t v3[] = {{"in", in}, {"title", "time histories (end of record)"}};
        st = aenl_plot_run("diagnose_timeseries", v3, 2, out, err);
    }
    if (st == AENL_OK)
    {
        (void)snprintf(in, sizeof(in), "%s/gaps.csv", dir);
        (void)snprintf(out, sizeof(out), "%s/diagnose_gaps.png", dir);
        const aenl_plot_var_t v4[] = {{"in", in}, {"title", "gap per channel"}};
        st = aenl_plot_run("diagnose_gaps", v4, 2, out, err);
    }
    return st;
}

static aenl_status_t write_report(const aenl_diagnose_result_t *r, const char *path,
                                  aenl_err_t *err)
{
    aenl_outfile_t of;
    const aenl_status_t st = aenl_outfile_open(&of, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    aenl_diagnose_report(r, of.fp);
    return aenl_outfile_commit(&of, err);
}

/* Outputs under dir; a failure undoes them when the run ends (aenl_outfile_abort_all). */
static aenl_status_t write_outputs(const aenl_diagnose_result_t *r, const char *dir,
                                   const char *source, int plots, char *ini_path, size_t n,
                                   aenl_err_t *err)
{
    (void)snprintf(ini_path, n, "%s/updated.ini", dir);
    char report[4096];
    (void)snprintf(report, sizeof(report), "%s/report.txt", dir);
    aenl_status_t st = aenl_diagnose_write_ini(r, source, ini_path, err);
    if (st == AENL_OK)
    {
        st = write_report(r, report, err);
    }
    if (st == AENL_OK)
    {
        st = aenl_diagnose_write_data(r, dir, err);
    }
    if (st == AENL_OK && plots)
    {
        st = make_figures(r, dir, err);
    }
    return st;
}

static int diagnose_and_write(const char *measured, const char *model, const char *out, int json,
                              int plots, const aenl_diagnose_opts_t *opts);

/* The command line of `aenl diagnose`. */
typedef struct
{
    const char *measured, *model, *out;
    int json, plots;
    aenl_diagnose_opts_t o;
} diag_args_t;

/* A whole-number option `name` in lo..hi: its value argv[*i + 1] into *lv. Nonzero after a
 * usage error (reported). */
static int long_option(int argc, char **argv, int *i, const char *name, long lo, long hi,
                       const char **v, long *lv)
{
    return (*v = aenl_cli_value(k_cmd, argc, argv, i)) == NULL ||
           aenl_cli_parse_long(k_cmd, name, *v, lo, hi, lv) != 0;
}

/* The options that set a number of the diagnosis (argv[*i] is a). Returns 1 when a is one of
 * them and its value is good, 0 when a is none of them, -1 after a usage error (reported). */
static int number_option(int argc, char **argv, int *i, const char *a, aenl_diagnose_opts_t *o)
{
    const char *v = NULL;
    long lv = 0;
    if (strcmp(a, "--replicates") == 0)
    {
        if (long_option(argc, argv, i, "--replicates", 2, 16, &v, &lv))
        {
            return -1;
        }
        o->n_replicates = (unsigned)lv;
    }
    else if (strcmp(a, "--refine") == 0)
    {
        if (long_option(argc, argv, i, "--refine", 0, AENL_DIAGNOSE_MAX_CAND, &v, &lv))
        {
            return -1;
        }
        o->n_refine = (unsigned)lv;
    }
    else if (strcmp(a, "--max-evals") == 0)
    {
        if (long_option(argc, argv, i, "--max-evals", 4, 1000, &v, &lv))
        {
            return -1;
        }
        o->max_evals = (unsigned)lv;
    }
    else if (strcmp(a, "--summary-records") == 0)
    {
        if (long_option(argc, argv, i, "--summary-records", 0, 4096, &v, &lv))
        {
            return -1;
        }
        if (lv > 0 && lv < 32)
        {
            aenl_cli_error(k_cmd, "--summary-records: %s must be 0 or 32..4096", v);
            return -1;
        }
        o->summary_records = (unsigned)lv;
    }
    else if (strcmp(a, "--jobs") == 0)
    {
        if (long_option(argc, argv, i, "--jobs", 1, AENL_MAX_JOBS, &v, &lv))
        {
            return -1;
        }
        aenl_set_jobs((unsigned)lv);
    }
    else if (strcmp(a, "--seed") == 0)
    {
        if (long_option(argc, argv, i, "--seed", 0, 2147483647L, &v, &lv))
        {
            return -1;
        }
        o->noise_seed = (uint64_t)lv;
    }
    else if (strcmp(a, "--penalty") == 0)
    {
        if ((v = aenl_cli_value(k_cmd, argc, argv, i)) == NULL ||
            aenl_cli_parse_double(k_cmd, "--penalty", v, &o->penalty) != 0)
        {
            return -1;
        }
        if (!(o->penalty >= 0.0))
        {
            aenl_cli_error(k_cmd, "--penalty: %s must be >= 0", v);
            return -1;
        }
    }
    else
    {
        return 0;
    }
    return 1;
}

/* Reads the options into d; returns the exit code when the command ends here (--help, a usage
 * error), -1 otherwise. */
static int parse_args(int argc, char **argv, diag_args_t *d)
{
    memset(d, 0, sizeof(*d));
    d->plots = 1;
    aenl_diagnose_opts_default(&d->o);
    for (int i = 1; i < argc; ++i)
    {
        const char *a = argv[i];
        const char **value = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
        {
            help();
            return AENL_EXIT_OK;
        }
        if (strcmp(a, "--measured") == 0)
        {
            value = &d->measured;
        }
        else if (strcmp(a, "--model") == 0)
        {
            value = &d->model;
        }
        else if (strcmp(a, "--out") == 0)
        {
            value = &d->out;
        }
        else if (strcmp(a, "--time") == 0)
        {
            value = &d->o.time_column;
        }
        else if (strcmp(a, "--json") == 0)
        {
            d->json = 1;
            aenl_cli_set_notes(0);
        }
        else if (strcmp(a, "--no-plots") == 0)
        {
            d->plots = 0;
        }
        else if (strcmp(a, "-v") == 0)
        {
            d->o.verbose = 1;
        }
        else
        {
            const int known = number_option(argc, argv, &i, a, &d->o);
            if (known < 0)
            {
                return AENL_EXIT_USAGE;
            }
            if (known == 0)
            {
                aenl_cli_error(k_cmd, "unknown argument %s (aenl diagnose --help)", a);
                return AENL_EXIT_USAGE;
            }
        }
        if (value != NULL && (*value = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
        {
            return AENL_EXIT_USAGE;
        }
    }
    aenl_cli_set_time_column(d->o.time_column);
    if (d->measured == NULL || d->model == NULL)
    {
        aenl_cli_error(k_cmd, "needs --measured DATA.csv and --model BASE.ini (aenl diagnose "
                              "--help)");
        return AENL_EXIT_USAGE;
    }
    return -1;
}

/* The output folder, made unless it exists (*created says which). Nonzero after an error
 * (reported). */
static int make_out_dir(const char *out, int *created)
{
    struct stat sb;
    if (mkdir(out, 0777) == 0)
    {
        *created = 1;
    }
    else if (errno != EEXIST || stat(out, &sb) != 0 || !S_ISDIR(sb.st_mode))
    {
        aenl_cli_error(k_cmd, "--out %s: cannot create the folder (%s)", out,
                       errno == EEXIST ? "a file of that name exists" : strerror(errno));
        return -1;
    }
    return 0;
}

int aenl_cmd_diagnose(int argc, char **argv)
{
    diag_args_t d;
    const int done = parse_args(argc, argv, &d);
    if (done >= 0)
    {
        return done;
    }
    const int plots = d.plots && d.out != NULL && aenl_plot_available();
    /* The output folder first: a bad --out fails before minutes of simulation. */
    int created = 0;
    if (d.out != NULL && make_out_dir(d.out, &created) != 0)
    {
        return AENL_EXIT_USAGE;
    }
    const int rc0 = diagnose_and_write(d.measured, d.model, d.out, d.json, plots, &d.o);
    if (rc0 != AENL_EXIT_OK && created)
    {
        aenl_outfile_abort_all(); /* the outputs written so far go first */
        (void)rmdir(d.out);       /* only when we made it and it stayed empty */
    }
    return rc0;
}

static int diagnose_and_write(const char *measured, const char *model, const char *out, int json,
                              int plots, const aenl_diagnose_opts_t *opts)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_model_t base;
    aenl_sim_run_t run;
    if (aenl_sim_load_ini(model, &base, &run, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    aenl_table_t t;
    if (aenl_table_read(measured, &t, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    if (aenl_cli_check_record(k_cmd, &t, measured, -1) != 0)
    {
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    aenl_diagnose_result_t r;
    /* a bar on a terminal, unless the -v lines tell the progress already */
    aenl_cli_bar_t bar;
    aenl_cli_bar_begin(&bar, k_cmd, "searching");
    aenl_diagnose_opts_t o = *opts;
    o.progress = opts->verbose ? NULL : &bar.progress;
    aenl_status_t st = aenl_diagnose_run(&t, &base, &run, &o, &r, &err);
    aenl_cli_bar_end(&bar);
    aenl_table_free(&t);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s: %s", measured, err.msg);
        return st == AENL_E_DIM ? AENL_EXIT_FAIL : AENL_EXIT_USAGE;
    }
    char ini_path[4096] = "";
    if (out != NULL)
    {
        char source[2048];
        (void)snprintf(source, sizeof(source), "--measured %s --model %s", measured, model);
        st = write_outputs(&r, out, source, plots, ini_path, sizeof(ini_path), &err);
        if (st != AENL_OK)
        {
            aenl_cli_error(k_cmd, "%s", err.msg);
            aenl_diagnose_result_free(&r);
            return AENL_EXIT_USAGE;
        }
    }
    int rc = AENL_EXIT_OK;
    if (json)
    {
        char *s = aenl_diagnose_json(&r, out != NULL ? ini_path : NULL);
        if (s == NULL)
        {
            aenl_cli_error(k_cmd, "out of memory (JSON)");
            rc = AENL_EXIT_FAIL;
        }
        else
        {
            printf("%s\n", s);
            free(s);
        }
    }
    else
    {
        aenl_diagnose_report(&r, stdout);
        if (out != NULL)
        {
            printf("updated model: %s (aenl simulate %s -o sim.csv)%s\n", ini_path, ini_path,
                   plots ? "; figures: diagnose_*.png" : "");
        }
    }
    aenl_diagnose_result_free(&r);
    return rc;
}
