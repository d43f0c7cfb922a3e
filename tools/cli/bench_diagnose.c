/* SPDX-License-Identifier: MIT */
/**
 * @file bench_diagnose.c
 * @brief `aenl bench diagnose`: the full hidden-effect matrix (every built-in case, both models,
 *        SNR 3, truth seeds the diagnosis never sees), one line per case: truth, what was named,
 *        parameter errors, gap before/after, runtime. Figures are printed, never asserted.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_diagnose.h"
#include "aenl_diagnose_cases.h"
#include "aenl_evalsuite.h"

static const char *const k_cmd = "bench diagnose";

typedef struct
{
    int long_rec, verbose, rk4, dryden, bound;
    long summary_records; /* -1: the default */
} bd_opts_t;

/* Records and sensitivity seeds of --bound (aenl_diagnose_case_bound). */
#define BOUND_RECORDS 96u
#define BOUND_JAC     32u

static void help(void)
{
    printf(
        "usage: aenl bench diagnose [--long] [--seed S] [--seeds N] [--case NAME] [--rk4]\n"
        "                           [--dryden] [--bound] [--summary-records N] [-v]\n\n"
        "Diagnoses every built-in hidden-effect case (tools/bench/aenl_diagnose_cases.c): truth\n"
        "parameters and seeds drawn from S, S+1, ... (N seeds, default 1), SNR 3, a baseline\n"
        "lacking the effect. --long uses 60 s at 1 kHz (3-DOF) and 12000 samples (2-DOF).\n"
        "--rk4 measures the truth with naive fixed-step RK4 (%u steps a sample, no event\n"
        "location, hysteresis without sticking) and --dryden drives it with the Dryden gust\n"
        "spectrum, while the diagnosis simulates its candidates as always (event-located\n"
        "integrator, the baseline's first-order gusts): a simulator it does not share.\n"
        "Goals: effect and DOF named, parameters within 15 %%, gap reduced 5-fold;\n"
        "null cases: none, gap within 2x the noise floor.\n"
        "--bound also prints each case's information floor: the standard deviation of its\n"
        "parameters that an efficient estimator on record summaries (mean, std, kurtosis,\n"
        "peak frequency, 2nd and 3rd harmonics of every channel) could reach on records of\n"
        "the truth's test (%u of them, sensitivities over %u seeds; docs/diagnose.md,\n"
        "\"Hidden-effect results\").\n"
        "--summary-records N: records of the diagnosis's summary fit (default 64; 0: off).\n",
        (unsigned)AENL_EVAL_RK4_STEPS, BOUND_RECORDS, BOUND_JAC);
}

typedef struct
{
    unsigned n, named_ok, params_ok, gap_ok;
    unsigned n_bounded, bounded_ok; /* --bound: cases whose floors allow 15 % at 2 sd; met */
    double seconds;
} tally_t;

/* --bound: the case's information floor, one line. */
static void print_bound(const aenl_diagnose_case_t *c, int params_ok, tally_t *t)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    double sd[AENL_DIAGNOSE_MAX_PAR] = {0};
    size_t np = 0;
    if (aenl_diagnose_case_bound(c, BOUND_RECORDS, BOUND_JAC, sd, &np, &err) != AENL_OK)
    {
        printf("  information floor: %s\n", err.msg);
        return;
    }
    if (np == 0u)
    {
        return;
    }
    printf("  information floor (sd, %% of truth):");
    double worst = 0.0;
    for (size_t k = 0; k < np; ++k)
    {
        if (isfinite(sd[k]))
        {
            printf(" %s %.2f", aenl_diagnose_param_name(c->effect, k), 100.0 * sd[k]);
        }
        else
        {
            printf(" %s not determined", aenl_diagnose_param_name(c->effect, k));
        }
        worst = fmax(worst, sd[k]);
    }
    const int allows = 2.0 * worst <= 0.15;
    printf("  -> 15 %% at 2 sd %s\n", allows ? "within reach" : "below the floor");
    t->n_bounded += (unsigned)allows;
    t->bounded_ok += (unsigned)(allows && params_ok);
}

static void run_case(size_t k, uint64_t seed, const bd_opts_t *bo, tally_t *t)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_diagnose_case_t c;
    aenl_table_t meas;
    aenl_status_t made = aenl_diagnose_case_make(k, seed, bo->long_rec, &c, &err);
    if (made == AENL_OK)
    {
        c.truth_rk4_steps = bo->rk4 ? (unsigned)AENL_EVAL_RK4_STEPS : 0u; /* as bench identify */
        if (bo->dryden)
        {
            c.truth_run.turb_spectrum = AENL_SIM_GUST_DRYDEN;
        }
        made = aenl_diagnose_case_measure(&c, &meas, &err);
    }
    if (made != AENL_OK)
    {
        printf("%-20s %4llu  error: %s\n", c.name, (unsigned long long)seed, err.msg);
        return;
    }
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    o.verbose = bo->verbose;
    if (bo->summary_records >= 0)
    {
        o.summary_records = (unsigned)bo->summary_records;
    }
    aenl_diagnose_result_t r;
    const aenl_status_t st = aenl_diagnose_run(&meas, &c.base, &c.base_run, &o, &r, &err);
    aenl_table_free(&meas);
    if (st != AENL_OK)
    {
        printf("%-20s %4llu  error: %s\n", c.name, (unsigned long long)seed, err.msg);
        return;
    }
    const int named = r.effect == c.effect && (c.effect == AENL_DIAGNOSE_NONE || r.dof == c.dof);
    double rel[AENL_DIAGNOSE_MAX_PAR] = {0};
    size_t np = 0;
    if (named)
    {
        np = aenl_diagnose_param_errors(c.effect, &c.truth.law[c.dof], &r.updated.law[c.dof], rel);
    }
    double worst = 0.0;
    for (size_t i = 0; i < np; ++i)
    {
        worst = fmax(worst, rel[i]);
    }
    const size_t nc = r.n_channels;
    const double ratio = r.gap_before[nc] / fmax(r.gap_after[nc], 1e-300);
    const double floor_ratio = r.gap_before[nc] / fmax(r.floor_before[nc], 1e-300);
    const int gap_ok = c.effect == AENL_DIAGNOSE_NONE ? (floor_ratio <= 2.0) : (ratio >= 5.0);
    const int params_ok = named && worst <= 0.15;
    char errs[64] = "-";
    size_t len = 0;
    for (size_t i = 0; i < np && len < sizeof(errs); ++i)
    {
        const int w =
            snprintf(errs + len, sizeof(errs) - len, "%s%.1f", i ? "/" : "", 100.0 * rel[i]);
        len += w > 0 ? (size_t)w : 0u;
    }
    char chi[128] = "";
    const int agrees = aenl_diagnose_baseline_agrees(&r);
    if (r.chi2_dof > 0u && r.rival < r.n_cand)
    {
        (void)snprintf(chi, sizeof(chi), "  chi2 %.3g/%zu%s%s; rival %s %s %.3g/%zu%s", r.chi2,
                       r.chi2_dof, r.summary_rejected ? " rejected" : "",
                       r.by_summaries ? " (named by the summaries)" : "",
                       aenl_diagnose_effect_name(r.cand[r.rival].effect),
                       aenl_diagnose_dof_name(r.cand[r.rival].dof), r.rival_chi2, r.rival_chi2_dof,
                       r.rival_rejected ? " rejected" : "");
    }
    else if (r.chi2_dof > 0u)
    {
        (void)snprintf(chi, sizeof(chi), "  chi2 %.3g/%zu%s", r.chi2, r.chi2_dof,
                       r.summary_rejected ? " rejected" : "");
    }
    else if (agrees >= 0)
    {
        (void)snprintf(chi, sizeof(chi), "  baseline's summaries p %.2f%s", r.base_test.p,
                       agrees ? "" : " rejected");
    }
    printf(
        "%-20s %4llu  %-10s %-6s -> %-10s %-6s %-3s  err%% %-16s  gap %.3g -> %.3g (x%.1f, "
        "floor %.3g)  %4u sims %6.1f s  %s%s\n",
        c.name, (unsigned long long)seed, aenl_diagnose_effect_name(c.effect),
        c.effect == AENL_DIAGNOSE_NONE ? "-" : aenl_diagnose_dof_name(c.dof),
        aenl_diagnose_effect_name(r.effect),
        r.effect == AENL_DIAGNOSE_NONE ? "-" : aenl_diagnose_dof_name(r.dof), named ? "ok" : "NO",
        errs, r.gap_before[nc], r.gap_after[nc], ratio, r.floor_after[nc], r.n_sims, r.seconds,
        (named && (params_ok || c.effect == AENL_DIAGNOSE_NONE) && gap_ok) ? "PASS" : "MISS", chi);
    if (bo->bound && named)
    {
        print_bound(&c, params_ok, t);
    }
    (void)fflush(stdout);
    t->n++;
    t->named_ok += (unsigned)named;
    t->params_ok += (unsigned)(params_ok || (named && c.effect == AENL_DIAGNOSE_NONE));
    t->gap_ok += (unsigned)gap_ok;
    t->seconds += r.seconds;
    aenl_diagnose_result_free(&r);
}

int aenl_bench_diagnose(int argc, char **argv)
{
    bd_opts_t bo;
    memset(&bo, 0, sizeof(bo));
    bo.summary_records = -1;
    long seed = 101, n_seeds = 1;
    const char *only = NULL;
    for (int i = 1; i < argc; ++i)
    {
        const char *a = argv[i];
        const char *v = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
        {
            help();
            return AENL_EXIT_OK;
        }
        if (strcmp(a, "--long") == 0)
        {
            bo.long_rec = 1;
        }
        else if (strcmp(a, "-v") == 0)
        {
            bo.verbose = 1;
        }
        else if (strcmp(a, "--rk4") == 0)
        {
            bo.rk4 = 1;
        }
        else if (strcmp(a, "--dryden") == 0)
        {
            bo.dryden = 1;
        }
        else if (strcmp(a, "--bound") == 0)
        {
            bo.bound = 1;
        }
        else if (strcmp(a, "--summary-records") == 0)
        {
            if ((v = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL ||
                aenl_cli_parse_long(k_cmd, "--summary-records", v, 0, 4096, &bo.summary_records) !=
                    0)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--seed") == 0)
        {
            if ((v = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL ||
                aenl_cli_parse_long(k_cmd, "--seed", v, 0, 1000000000L, &seed) != 0)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--seeds") == 0)
        {
            if ((v = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL ||
                aenl_cli_parse_long(k_cmd, "--seeds", v, 1, 1000, &n_seeds) != 0)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--case") == 0)
        {
            if ((only = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else
        {
            aenl_cli_error(k_cmd, "unknown option %s (aenl bench diagnose --help)", a);
            return AENL_EXIT_USAGE;
        }
    }
    printf("aenl bench diagnose: hidden-effect matrix, SNR 3, %s records; truth by %s, %s gusts\n",
           bo.long_rec ? "long (3-DOF 60 s at 1 kHz, 2-DOF 12000 samples)"
                       : "short (3-DOF 12 s at 500 Hz, 2-DOF 6000 samples)",
           bo.rk4 ? "naive RK4" : "the event-located integrator",
           bo.dryden ? "Dryden" : "first-order");
    printf("%-20s %4s  %-17s -> %-17s %-3s  %-21s  %s\n", "case", "seed", "truth", "named", "",
           "param errors (%)", "gap before -> after");
    tally_t t;
    memset(&t, 0, sizeof(t));
    int found = only == NULL;
    for (long s = 0; s < n_seeds; ++s)
    {
        for (size_t k = 0; k < aenl_diagnose_n_cases(); ++k)
        {
            aenl_diagnose_case_t c;
            aenl_err_t err;
            aenl_err_clear(&err);
            (void)aenl_diagnose_case_make(k, 0, 0, &c, &err);
            if (only != NULL && strcmp(only, c.name) != 0)
            {
                continue;
            }
            found = 1;
            run_case(k, (uint64_t)(seed + s), &bo, &t);
        }
    }
    if (!found)
    {
        aenl_cli_error(k_cmd, "no case named '%s'", only);
        return AENL_EXIT_USAGE;
    }
    printf("summary: %u cases; named %u/%u, parameters %u/%u, gap goal %u/%u; %.1f s diagnosing "
           "(%.1f s per case)\n",
           t.n, t.named_ok, t.n, t.params_ok, t.n, t.gap_ok, t.n, t.seconds,
           t.n ? t.seconds / t.n : 0.0);
    if (bo.bound)
    {
        printf("information floor: 15 %% at 2 sd within reach in %u of the named cases with "
               "parameters; parameters within 15 %% in %u of those\n",
               t.n_bounded, t.bounded_ok);
    }
    return AENL_EXIT_OK;
}
