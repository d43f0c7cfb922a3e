/* SPDX-License-Identifier: MIT */
/**
 * @file bench_null.c
 * @brief `aenl bench null [--records N] [--from K] [--level A] [--verbose]`: the level of
 *        `identify` (its default method, the test) on linear records. Every record is an exactly
 * linear model of the project's simulator, so every nonlinear verdict is a false positive; the
 * bench prints their share per regime, with and without measurement noise, beside the level.
 *
 * Design: 6 regimes (free decay, kicked decay train, first-order and Dryden turbulence, swept
 * sine and multisine force without the force given) x 2 models (airfoil2dof, section3dof) x 5
 * noise levels (none, SNR 10, 5, 3, 2) x 5 draws = 300 records. Record i draws its speed,
 * length, excitation and noise from its own seeded generator, so it is the same record in any
 * run and alone (--from). Figures are printed, never asserted.
 */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_clock.h"
#include "aenl_tools/aenl_nltest.h"
#include "aenl_tools/aenl_rng.h"
#include "aenl_tools/aenl_sim.h"

#define N_REG     6
#define N_NOISE   5
#define N_DRAWS   5
#define N_RECORDS 300L /* N_REG x 2 models x N_NOISE x N_DRAWS */
#define PER_MODEL 25u  /* N_NOISE x N_DRAWS */
#define PER_REG   50u  /* 2 models x PER_MODEL */
#define SEED_BASE 20240611u
#define DEG       0.017453292519943295

static const char *const k_cmd = "bench null";
static const char *const k_regime[N_REG] = {"free decay",        "kicked train", "turbulence 1st",
                                            "turbulence Dryden", "swept sine",   "multisine"};
static const double k_snr[N_NOISE] = {0.0, 10.0, 5.0, 3.0, 2.0};

static double unif(aenl_rng_t *g, double a, double b)
{
    return a + (b - a) * aenl_rng_uniform(g);
}

/* Record i: its regime, model and noise, then the draws of its own generator. */
static void make_record(size_t i, aenl_sim_model_t *m, aenl_sim_run_t *run, int *reg)
{
    const int noise = (int)((i / N_DRAWS) % N_NOISE);
    const int air = (int)((i / PER_MODEL) % 2u) == 0;
    *reg = (int)(i / PER_REG);
    aenl_rng_t g;
    aenl_rng_seed(&g, SEED_BASE + (uint64_t)i);
    const aenl_sim_type_t type = air ? AENL_SIM_AIRFOIL2DOF : AENL_SIM_SECTION3DOF;
    aenl_sim_model_default(m, type);
    aenl_sim_run_default(run, type);
    aenl_sim_set_velocity(m, air ? unif(&g, 3.0, 5.5) : unif(&g, 8.0, 20.0));
    run->dt = air ? 0.5 : 0.002;
    /* a free decay rings down in the first part of 6 000-8 000 samples; else 6 000-16 000 */
    const double n = *reg == 0 ? unif(&g, 6000.0, 8000.0) : unif(&g, 6000.0, 16000.0);
    run->duration = floor(n - 1.0) * run->dt;
    const int pitch = unif(&g, 0.0, 1.0) < 0.5;
    const double sign = unif(&g, 0.0, 1.0) < 0.5 ? -1.0 : 1.0;
    const aenl_sim_dof_t dof = pitch ? AENL_SIM_DOF_PITCH : AENL_SIM_DOF_PLUNGE;
    switch (*reg)
    {
        case 0: /* plunge: xi = h/b (airfoil), metres (section) */
            m->x0[dof] = sign * (pitch ? unif(&g, 1.0, 3.0) * DEG
                                       : (air ? unif(&g, 0.02, 0.05) : unif(&g, 0.002, 0.006)));
            break;
        case 1:
            run->kicks = 1;
            run->kick_dof = dof;
            run->kick_every =
                round((air ? unif(&g, 150.0, 400.0) : unif(&g, 1.0, 3.0)) / run->dt) * run->dt;
            run->kick_rate = air ? (pitch ? unif(&g, 0.004, 0.012) : unif(&g, 0.001, 0.004))
                                 : (pitch ? unif(&g, 1.0, 3.0) : unif(&g, 0.05, 0.15));
            run->kick_rate_max = 1.5 * run->kick_rate;
            run->kick_sign = AENL_SIM_KICK_RANDOM;
            run->kick_seed = SEED_BASE + 7u * (uint64_t)i + 1u;
            break;
        case 2:
        case 3:
            run->turbulence = 1;
            run->turb_spectrum = *reg == 2 ? AENL_SIM_GUST_FIRST_ORDER : AENL_SIM_GUST_DRYDEN;
            run->turb_intensity = unif(&g, 0.002, 0.01);
            run->turb_length = unif(&g, 2.0, 8.0) * (air ? 1.0 : m->section.b);
            run->turb_seed = SEED_BASE + 7u * (uint64_t)i + 3u;
            break;
        default:
            run->force = *reg == 4 ? AENL_SIM_FORCE_SWEEP : AENL_SIM_FORCE_MULTISINE;
            run->force_dof = dof;
            run->force_amp = pitch ? unif(&g, 0.2, 1.0) * DEG
                                   : (air ? unif(&g, 0.005, 0.02) : unif(&g, 0.0005, 0.002));
            run->force_f0 = air ? 0.005 : 0.5; /* a band over the models' modes */
            run->force_f1 = air ? 0.2 : 20.0;
            run->force_log = *reg == 4 && unif(&g, 0.0, 1.0) < 0.5;
            run->force_period = air ? 2000.0 : 0.0;
            run->force_seed = SEED_BASE + 7u * (uint64_t)i + 9u;
            break;
    }
    run->snr = k_snr[noise];
    run->noise_seed = SEED_BASE + 7u * (uint64_t)i + 5u;
}

typedef struct
{
    long records, from;
    double level;
    int verbose;
    int force_given; /* the forced records' force goes to the test as a known input */
    int impulsive;   /* the kicked records are declared driven by impulses (--impulsive) */
} null_args_t;

static int parse(int argc, char **argv, null_args_t *a)
{
    a->records = N_RECORDS;
    a->from = 0;
    a->level = 0.01;
    a->verbose = 0;
    a->force_given = 0;
    a->impulsive = 0;
    for (int i = 1; i < argc; ++i)
    {
        const char *s = argv[i];
        if (strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0)
        {
            printf("usage: aenl bench null [--records N] [--from K] [--level A] [--verbose]\n"
                   "                       [--force-given] [--impulsive]\n\n"
                   "The level of `identify` (the test) on %ld linear records of the\n"
                   "simulator (free decays, kicked decay trains, first-order and Dryden\n"
                   "turbulence, swept-sine and multisine forcing without the force given; both\n"
                   "models; no noise and SNR 10, 5, 3, 2): every nonlinear verdict is a false\n"
                   "positive. --records N runs records K..N-1 (--from K), --level A the test's\n"
                   "level (0.01), --verbose a line per record, --force-given the swept-sine\n"
                   "and multisine records with their force as a known input (--input),\n"
                   "--impulsive the kicked trains declared driven by impulses (identify\n"
                   "--impulsive).\n"
                   "About 3 s a record.\n",
                   N_RECORDS);
            return 1;
        }
        if (strcmp(s, "--verbose") == 0 || strcmp(s, "-v") == 0)
        {
            a->verbose = 1;
            continue;
        }
        if (strcmp(s, "--force-given") == 0)
        {
            a->force_given = 1;
            continue;
        }
        if (strcmp(s, "--impulsive") == 0)
        {
            a->impulsive = 1;
            continue;
        }
        const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
        if (v == NULL)
        {
            return -1;
        }
        if (strcmp(s, "--records") == 0 || strcmp(s, "--from") == 0)
        {
            long x = 0;
            if (aenl_cli_parse_long(k_cmd, s, v, strcmp(s, "--records") == 0 ? 1 : 0, N_RECORDS,
                                    &x) != 0)
            {
                return -1;
            }
            *(strcmp(s, "--records") == 0 ? &a->records : &a->from) = x;
        }
        else if (strcmp(s, "--level") == 0)
        {
            char *end = NULL;
            a->level = aenl_strtod_decimal(v, &end);
            if (end == v || *end != '\0' || !(a->level > 0.0 && a->level < 0.5))
            {
                aenl_cli_error(k_cmd, "--level: '%s' is not a test level (0 < A < 0.5)", v);
                return -1;
            }
        }
        else
        {
            aenl_cli_error(k_cmd, "unknown argument %s (aenl bench null --help)", s);
            return -1;
        }
    }
    return 0;
}

/* One record: 1 when the test calls it nonlinear, 0 when linear, -1 when it could not run;
 * *reg its regime, *noisy 1 with measurement noise. */
static int run_record(size_t i, const null_args_t *a, double *secs, int *reg, int *noisy)
{
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    make_record(i, &m, &run, reg);
    *noisy = run.snr > 0.0;
    aenl_sim_result_t r;
    aenl_err_t err;
    aenl_err_clear(&err);
    if (aenl_sim_simulate(&m, &run, &r, &err) != AENL_OK)
    {
        printf("  record %zu not simulated: %s\n", i, err.msg);
        return -1;
    }
    const size_t n = r.n_samples;
    const size_t nc = r.n_channels;
    const double *cols[3] = {r.y, r.y + n, r.y + 2u * n};
    aenl_nlt_opts_t o;
    aenl_nlt_opts_default(&o);
    o.level = a->level;
    double *force = NULL;
    const double *in[1] = {NULL};
    if (a->force_given && run.force != AENL_SIM_FORCE_NONE)
    {
        force = (double *)malloc(n * sizeof(double));
        if (force == NULL || aenl_sim_force_series(&run, n, force, &err) != AENL_OK)
        {
            printf("  record %zu: no force series: %s\n", i,
                   force == NULL ? "out of memory" : err.msg);
            free(force);
            aenl_sim_result_free(&r);
            return -1;
        }
        in[0] = force;
        o.input = in;
        o.n_input = 1;
    }
    o.impulsive = a->impulsive && run.kicks;
    aenl_nlt_result_t res;
    const double t0 = aenl_now_s();
    const aenl_status_t st = aenl_nlt_run_columns(cols, n, nc, &o, &res, &err);
    free(force);
    *secs = aenl_now_s() - t0;
    int out = -1;
    if (st != AENL_OK)
    {
        printf("  record %zu: the test failed: %s\n", i, err.msg);
    }
    else
    {
        out = res.verdict_class != AENL_CLASS_LINEAR ? 1 : 0;
        if (a->verbose)
        {
            char snr[16];
            (void)snprintf(snr, sizeof(snr), run.snr > 0.0 ? "%g" : "inf", run.snr);
            printf("  %3zu %-18s %-11s SNR %-4s %6zu samples %2zu states %3zu impulses  %-12s "
                   "p %.2e  %.1f s\n",
                   i, k_regime[*reg], nc == 2 ? "airfoil2dof" : "section3dof", snr, n, res.n_states,
                   res.n_impulses, aenl_nlt_class_name(res.verdict_class, res.undetermined),
                   res.verdict >= 0 ? res.ch[res.verdict].p : 1.0, *secs);
        }
    }
    aenl_sim_result_free(&r);
    return out;
}

int aenl_bench_null(int argc, char **argv)
{
    null_args_t a;
    const int pr = parse(argc, argv, &a);
    if (pr != 0)
    {
        return pr > 0 ? AENL_EXIT_OK : AENL_EXIT_USAGE;
    }
    printf("level of identify (the test, level %g) on linear records: records %ld..%ld of "
           "%ld%s%s\n",
           a.level, a.from, a.records - 1, N_RECORDS,
           a.force_given ? "; forced records with their force as a known input" : "",
           a.impulsive ? "; kicked records declared driven by impulses (--impulsive)" : "");
    size_t cnt[N_REG][2][2] = {{{0}}}; /* [regime][noisy][nonlinear] */
    size_t failed = 0;
    double secs_all = 0.0;
    aenl_cli_bar_t bar; /* with a line per record (--verbose), those lines show the progress */
    aenl_cli_bar_begin(&bar, "bench null", "records");
    bar.on = bar.on && !a.verbose;
    for (long i = a.from; i < a.records; ++i)
    {
        int reg = 0;
        int noisy = 0;
        double secs = 0.0;
        const int v = run_record((size_t)i, &a, &secs, &reg, &noisy);
        aenl_cli_bar_update(&bar, (size_t)(i - a.from + 1), (size_t)(a.records - a.from));
        secs_all += secs;
        if (v < 0)
        {
            ++failed;
            continue;
        }
        ++cnt[reg][noisy][v];
        (void)fflush(stdout);
    }
    aenl_cli_bar_end(&bar);
    printf("\nregime               with noise (SNR 10-2)      noise-free\n");
    size_t tot[2] = {0, 0};
    size_t pos[2] = {0, 0};
    for (int r = 0; r < N_REG; ++r)
    {
        printf("  %-18s", k_regime[r]);
        for (int z = 1; z >= 0; --z)
        {
            const size_t nr = cnt[r][z][0] + cnt[r][z][1];
            tot[z] += nr;
            pos[z] += cnt[r][z][1];
            char cell[48];
            (void)snprintf(cell, sizeof(cell), "%zu/%zu (%.1f %%)", cnt[r][z][1], nr,
                           nr > 0 ? 100.0 * (double)cnt[r][z][1] / (double)nr : 0.0);
            printf("  %-24s", nr > 0 ? cell : "-");
        }
        printf("\n");
    }
    printf("  %-18s  %zu/%zu %-16s  %zu/%zu\n", "all", pos[1], tot[1], "", pos[0], tot[0]);
    printf("nonlinear verdicts on linear records should be about the level (%g); %zu records "
           "failed; %.2f s a record\n",
           a.level, failed,
           tot[0] + tot[1] > 0 ? secs_all / (double)(tot[0] + tot[1] + failed) : 0.0);
    return failed > 0 ? AENL_EXIT_FAIL : AENL_EXIT_OK;
}
