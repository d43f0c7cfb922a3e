/* SPDX-License-Identifier: MIT */
/**
 * @file bench_identify.c
 * @brief `aenl bench identify [--cases N] [--seed S] [--rk4] [--dryden] [--write DIR]
 *        [--verbose]`: the evaluation suite (aenl_evalsuite.h) through the
 *        identification pipeline (aenl_identify_run on the arrays in memory). Prints, per SNR,
 *        the confusion matrix (truth class x predicted class, insufficient included), the class
 *        accuracy, the correct-channel rate, the switching-point error as a fraction of the gap
 *        width, then the accuracy per regime, model and stratum, the cost of one classifier
 *        update on a realistic moments state, the classifier's state size (host double here,
 *        float32 core from aenl_classifier_bench_f32) and the wall time. Figures are printed,
 *        never asserted. --rk4 and --dryden make the records with another simulator
 *        (aenl_eval_options_t): the suite's designs (their amplitudes set by that simulator's
 *        pilot runs), integrated by naive fixed-step RK4 (no event location, no sticking) or
 *        driven by the Dryden gust spectrum, a look at how the verdicts carry over to data the
 *        method was not developed on.
 *
 * Scoring. Class: the verdict class (the named channel's, or linear / insufficient when no
 * channel is named). Channel: the named channel is the truth's; for a linear truth, no channel
 * named. Switching points: for a gap truth (freeplay, hysteresis) whose channel is named, each
 * true point is matched to the nearest predicted point of that channel; the error is
 * |predicted − true| / δ, pooled over the points; cases where the channel gives no point are
 * counted apart, and so are cases where the number of points differs.
 */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "aenl_cli.h"
#include "aenl/aenl.h"
#include "aenl_tools/aenl_clock.h"
#include "aenl_tools/aenl_nltest.h"
#include "aenl_evalsuite.h"
#include "aenl_tools/aenl_identify.h"
#include "aenl_tools/aenl_parallel.h"

static const char *const k_cmd = "bench identify";

#define N_TRUTH 4 /* linear, polynomial, freeplay, hysteresis = aenl_class_t 1..4 */
#define N_PRED  5 /* insufficient .. hysteresis = aenl_class_t 0..4 */
#define N_SNR   AENL_EVAL_N_SNR

static const char *const k_snr_name[N_SNR] = {"inf", "10", "3", "2"};
static const char *k_cls_short[N_PRED] = {"insuff", "linear", "poly", "freeplay", "hyster"};

/** Score of one case. */
typedef struct outcome
{
    aenl_eval_stratum_t st;
    int truth; /* aenl_class_t 1..4 */
    int pred;  /* aenl_class_t 0..4 */
    int class_ok;
    int channel_ok;
    int n_err; /* switching-point errors below (0 when not scored) */
    double err[AENL_EVAL_MAX_SWITCH];
    int count_differs; /* predicted point count != true count */
    int no_points;     /* gap truth, channel named right, but no point given */
    double confidence; /* the verdict's */
} outcome_t;

/* Confidence bands of the reliability table: [k_band[i], k_band[i + 1]) */
#define N_BANDS 5
/* --unknown-gusts: the model-based test's turbulence seed is the record's plus this (a prime far
 * from the diagnosis' own replicate steps) */
#define UNKNOWN_GUST_SEED_STEP 1000003u
static const double k_band[N_BANDS + 1] = {0.0, 0.5, 0.7, 0.9, 0.99, 1.0 + 1e-9};

/** Totals. */
typedef struct tally
{
    size_t n;
    size_t conf[N_SNR][N_TRUTH][N_PRED];
    size_t cases[N_SNR], class_ok[N_SNR], channel_ok[N_SNR];
    size_t gap_cases[N_SNR], no_points[N_SNR], count_differs[N_SNR], scored[N_SNR];
    double *err[N_SNR];
    size_t n_err[N_SNR], cap_err[N_SNR];
    /* breakdowns: [regime], [model], [variant][regime] x (cases, class ok, channel ok) */
    size_t by_regime[AENL_EVAL_N_REGIMES][3], by_model[2][3];
    size_t by_cell[AENL_EVAL_N_VARIANTS][AENL_EVAL_N_REGIMES][3];
    size_t rejections, cases_rejected, gen_failures, id_failures;
    double t_gen, t_id;
    /* each analysis alone: [0] core classifier, [1] restoring-force regression, [2] the whole
     * pipeline on the record alone (--model only); [SNR] x (class ok, channel ok) */
    size_t alone[3][N_SNR][2];
    size_t n_model;        /* --model: cases given the model-based test */
    size_t model_failures; /* of them, diagnoses that failed (the record's verdict kept) */
    size_t model_second;   /* of them, a second effect named (every case has one law at most) */
    double t_model;
    /* reliability of the verdict's confidence: per band, verdicts, right ones (class and
     * channel), sum of confidences; per regime, sum of (confidence - right)^2 */
    size_t band_n[N_BANDS], band_ok[N_BANDS];
    double band_conf[N_BANDS], brier[AENL_EVAL_N_REGIMES];
} tally_t;

typedef struct args
{
    long cases;
    unsigned long long seed;
    const char *write_dir;
    int verbose;
    int model;               /* --model: the model-based test on every case */
    int unknown_gusts;       /* --unknown-gusts: the test's turbulence seed is not the record's */
    int regime;              /* --regime: only these cases (-1 all) */
    long rows;               /* --rows: each record's first rows (0 all) */
    long from;               /* --from: the first case index run */
    int method_test;         /* --method test: identify --method test instead of the pipeline */
    int impulsive;           /* --impulsive: the kick trains (decays) declared driven by impulses */
    size_t samples;          /* samples x channels identified (for the cost per value) */
    aenl_eval_options_t sim; /* --rk4, --dryden */
} args_t;

static void usage(void)
{
    printf(
        "usage: aenl bench identify [--cases N] [--seed S] [--rk4] [--dryden] [--write DIR]\n"
        "                           [--verbose] [--regime R] [--rows N] [--model] [--from K]\n"
        "                           [--unknown-gusts] [--method moments|test] [--jobs N]\n"
        "                           [--impulsive]\n\n"
        "The identification evaluation suite: N cases (default 240: every stratum\n"
        "of class x DOF x model x regime x SNR once) generated from seed S (default 1) with\n"
        "the simulators, each identified by the `aenl identify` pipeline. --rk4 integrates\n"
        "the suite's designs with naive fixed-step RK4 (%d steps a sample, no event location,\n"
        "hysteresis without sticking) and --dryden drives the turbulence records with the\n"
        "Dryden gust spectrum: records from another simulator. --write DIR saves every\n"
        "case's INI (rerun with `aenl simulate`, plus --rk4 dt/%d for --rk4), the CSV of\n"
        "every miss and results.tsv; --verbose prints one line per case. --regime R (decay,\n"
        "lco, turbulence) runs only those cases, --from K only the cases K..N-1, --rows N each\n"
        "record's first N rows (>= 512).\n"
        "--model adds the model-based test of `identify --model` (a diagnosis against the\n"
        "case's model with its law made linear, under the case's conditions: its initial\n"
        "state, turbulence or kick train); the record alone's verdicts on the same cases are\n"
        "printed beside. It takes seconds to minutes a case. The test is given the case's\n"
        "turbulence seed, as for gusts that were measured or a record simulated from the INI;\n"
        "--unknown-gusts gives it another, as for gusts nobody measured (a real record).\n"
        "--method test identifies each record with `identify --method test` (the likelihood-\n"
        "based test on the record alone) instead; its undetermined verdicts are the 'undet'\n"
        "column, and its cost per value (samples x channels) is printed with the thread setting\n"
        "(--jobs N, 1..64, default one per processor; --jobs 1 for the one-core figure).\n"
        "--impulsive (with --method test): the decay cases, each a train of releases by\n"
        "kicks, are declared driven by impulses, as `identify --impulsive` declares a record\n"
        "(the other regimes are run as without it). --verbose gives each case's impulses\n"
        "('imp') and says 'jumps' where the test ran on the jump model.\n",
        AENL_EVAL_RK4_STEPS, AENL_EVAL_RK4_STEPS);
}

static int parse_args(int argc, char **argv, args_t *a)
{
    a->cases = 240;
    a->seed = 1;
    a->write_dir = NULL;
    a->verbose = 0;
    a->model = 0;
    a->unknown_gusts = 0;
    a->regime = -1;
    a->rows = 0;
    a->from = 0;
    a->method_test = 0;
    a->impulsive = 0;
    a->samples = 0;
    memset(&a->sim, 0, sizeof(a->sim));
    for (int i = 1; i < argc; ++i)
    {
        const char *s = argv[i];
        if (strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0)
        {
            usage();
            return 1;
        }
        if (strcmp(s, "--verbose") == 0 || strcmp(s, "-v") == 0)
        {
            a->verbose = 1;
        }
        else if (strcmp(s, "--rk4") == 0)
        {
            a->sim.rk4 = 1;
        }
        else if (strcmp(s, "--model") == 0)
        {
            a->model = 1;
        }
        else if (strcmp(s, "--impulsive") == 0)
        {
            a->impulsive = 1;
        }
        else if (strcmp(s, "--unknown-gusts") == 0)
        {
            a->unknown_gusts = 1;
        }
        else if (strcmp(s, "--regime") == 0)
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            if (v == NULL)
            {
                return -1;
            }
            for (int r = 0; r < (int)AENL_EVAL_N_REGIMES; ++r)
            {
                a->regime =
                    strcmp(v, aenl_eval_regime_name((aenl_eval_regime_t)r)) == 0 ? r : a->regime;
            }
            if (a->regime < 0)
            {
                aenl_cli_error(k_cmd, "--regime: '%s' is none of decay, lco, turbulence", v);
                return -1;
            }
        }
        else if (strcmp(s, "--from") == 0)
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            if (v == NULL || aenl_cli_parse_long(k_cmd, s, v, 0, 100000, &a->from) != 0)
            {
                return -1;
            }
        }
        else if (strcmp(s, "--jobs") == 0)
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            long jobs = 0;
            if (v == NULL || aenl_cli_parse_long(k_cmd, s, v, 1, AENL_MAX_JOBS, &jobs) != 0)
            {
                return -1;
            }
            aenl_set_jobs((unsigned)jobs);
        }
        else if (strcmp(s, "--rows") == 0)
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            if (v == NULL || aenl_cli_parse_long(k_cmd, s, v, 512, 2147483647, &a->rows) != 0)
            {
                return -1;
            }
        }
        else if (strcmp(s, "--method") == 0)
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            if (v == NULL)
            {
                return -1;
            }
            if (strcmp(v, "test") != 0 && strcmp(v, "moments") != 0)
            {
                aenl_cli_error(k_cmd, "--method: expected test or moments, got '%s'", v);
                return -1;
            }
            a->method_test = strcmp(v, "test") == 0;
        }
        else if (strcmp(s, "--dryden") == 0)
        {
            a->sim.spectrum = AENL_SIM_GUST_DRYDEN;
        }
        else if (strcmp(s, "--cases") == 0 || strcmp(s, "--seed") == 0)
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            long x = 0;
            if (v == NULL ||
                aenl_cli_parse_long(k_cmd, s, v, strcmp(s, "--cases") == 0 ? 1 : 0,
                                    strcmp(s, "--cases") == 0 ? 100000 : 2147483647, &x) != 0)
            {
                return -1;
            }
            if (strcmp(s, "--cases") == 0)
            {
                a->cases = x;
            }
            else
            {
                a->seed = (unsigned long long)x;
            }
        }
        else if (strcmp(s, "--write") == 0)
        {
            if ((a->write_dir = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return -1;
            }
        }
        else
        {
            aenl_cli_error(k_cmd, "unknown option '%s' (see --help)", s);
            return -1;
        }
    }
    return 0;
}

static int push_err(tally_t *t, unsigned lvl, double e)
{
    if (t->n_err[lvl] == t->cap_err[lvl])
    {
        const size_t cap = t->cap_err[lvl] ? 2 * t->cap_err[lvl] : 64;
        double *p = realloc(t->err[lvl], cap * sizeof(double));
        if (p == NULL)
        {
            return -1;
        }
        t->err[lvl] = p;
        t->cap_err[lvl] = cap;
    }
    t->err[lvl][t->n_err[lvl]++] = e;
    return 0;
}

/* Verdict of one analysis alone (0 the core classifier, 1 the restoring-force regression): the
 * nonlinear channel with the largest evidence, as aenl_identify_run names one. */
static void score_alone(const aenl_eval_case_t *c, const aenl_identify_result_t *r, int which,
                        tally_t *t)
{
    long v = -1;
    int cls = (int)AENL_CLASS_INSUFFICIENT;
    double best = 0.0;
    for (size_t k = 0; r != NULL && k < r->n_channels; ++k)
    {
        const aenl_identify_channel_t *ch = &r->ch[k];
        const int ck = which == 0 ? (int)ch->onboard.cls : (int)ch->rfs.cls;
        const double ev = which == 0 ? (double)ch->onboard.evidence : ch->rfs.evidence;
        if (ck == (int)AENL_CLASS_LINEAR && v < 0)
        {
            cls = ck;
        }
        if (ck > (int)AENL_CLASS_LINEAR && ev > best)
        {
            best = ev;
            v = (long)k;
            cls = ck;
        }
    }
    const unsigned l = c->stratum.snr_level;
    t->alone[which][l][0] += (size_t)(cls == (int)c->cls);
    t->alone[which][l][1] += (size_t)(c->channel_index < 0 ? v < 0 : v == c->channel_index);
}

/* The class, channel and confidence of a verdict (cls, channel v, conf; no result: ok 0);
 * returns 1 when its switching points are to be scored (a gap truth, its channel named). */
static int score_verdict(const aenl_eval_case_t *c, int ok, int cls, long v, double conf,
                         outcome_t *o)
{
    memset(o, 0, sizeof(*o));
    o->st = c->stratum;
    o->truth = (int)c->cls;
    o->pred = ok ? cls : (int)AENL_CLASS_INSUFFICIENT;
    if (o->pred < 0 || o->pred >= N_PRED)
    {
        o->pred = (int)AENL_CLASS_INSUFFICIENT;
    }
    o->class_ok = o->pred == o->truth;
    v = ok ? v : -1;
    o->channel_ok = c->channel_index < 0 ? v < 0 : v == c->channel_index;
    o->confidence = ok ? conf : 0.0;
    return ok && c->n_switch > 0 && o->channel_ok;
}

/* Score the identification of one case. */
static void score(const aenl_eval_case_t *c, const aenl_identify_result_t *r, outcome_t *o)
{
    const long v = r != NULL ? r->verdict : -1;
    if (!score_verdict(c, r != NULL, r != NULL ? (int)r->verdict_class : 0, v,
                       r != NULL ? r->verdict_confidence : 0.0, o))
    {
        return;
    }
    const aenl_classifier_result_t *cr = &r->ch[v].res;
    if (cr->n_switch == 0)
    {
        o->no_points = 1;
        return;
    }
    o->count_differs = (size_t)cr->n_switch != c->n_switch;
    for (size_t i = 0; i < c->n_switch; ++i)
    {
        double best = HUGE_VAL;
        for (unsigned j = 0; j < cr->n_switch; ++j)
        {
            best = fmin(best, fabs((double)cr->switch_points[j] - c->switch_points[i]));
        }
        o->err[o->n_err++] = best / c->gap;
    }
}

static int tally_add(tally_t *t, const outcome_t *o)
{
    const unsigned l = o->st.snr_level;
    ++t->n;
    ++t->cases[l];
    ++t->conf[l][o->truth - 1][o->pred];
    t->class_ok[l] += (size_t)o->class_ok;
    t->channel_ok[l] += (size_t)o->channel_ok;
    if (o->truth == (int)AENL_CLASS_FREEPLAY || o->truth == (int)AENL_CLASS_HYSTERESIS)
    {
        ++t->gap_cases[l];
        t->no_points[l] += (size_t)o->no_points;
        t->count_differs[l] += (size_t)o->count_differs;
        t->scored[l] += o->n_err > 0;
    }
    for (int i = 0; i < o->n_err; ++i)
    {
        if (push_err(t, l, o->err[i]) != 0)
        {
            return -1;
        }
    }
    const int right = o->class_ok && o->channel_ok;
    for (int b = 0; b < N_BANDS; ++b)
    {
        if (o->confidence >= k_band[b] && o->confidence < k_band[b + 1])
        {
            ++t->band_n[b];
            t->band_ok[b] += (size_t)right;
            t->band_conf[b] += o->confidence;
        }
    }
    t->brier[o->st.regime] += (o->confidence - right) * (o->confidence - right);
    size_t *cells[3] = {t->by_regime[o->st.regime], t->by_model[o->st.model],
                        t->by_cell[o->st.variant][o->st.regime]};
    for (int k = 0; k < 3; ++k)
    {
        cells[k][0] += 1;
        cells[k][1] += (size_t)o->class_ok;
        cells[k][2] += (size_t)o->channel_ok;
    }
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double quantile(double *v, size_t n, double q)
{
    if (n == 0 || v == NULL)
    {
        return (double)NAN;
    }
    qsort(v, n, sizeof(double), cmp_double);
    return v[(size_t)floor(q * (double)(n - 1) + 0.5)];
}

static double pct(size_t a, size_t b)
{
    return b > 0 ? 100.0 * (double)a / (double)b : (double)NAN;
}

static void print_points(const double *p, size_t n)
{
    printf("[");
    for (size_t i = 0; i < n; ++i)
    {
        printf("%s%.4g", i ? "," : "", p[i]);
    }
    printf("]");
}

static void print_verbose(const aenl_eval_case_t *c, const aenl_identify_result_t *r,
                          const outcome_t *o)
{
    printf("%4zu %-10s %-11s %-6s %-10s snr %-3s | truth %-10s %-5s ", c->index,
           aenl_eval_variant_name(c->stratum.variant),
           c->model.type == AENL_SIM_AIRFOIL2DOF ? "airfoil2dof" : "section3dof",
           aenl_eval_dof_name(c->stratum.dof), aenl_eval_regime_name(c->stratum.regime),
           k_snr_name[c->stratum.snr_level], k_cls_short[o->truth],
           c->channel[0] ? c->channel : "-");
    print_points(c->switch_points, c->n_switch);
    if (r == NULL)
    {
        printf(" | identify failed | MISS\n");
        return;
    }
    const long v = r->verdict;
    double pts[AENL_CLASSIFIER_MAX_SWITCH];
    size_t np = 0;
    if (v >= 0)
    {
        const aenl_classifier_result_t *cr = &r->ch[v].res;
        np = cr->n_switch;
        for (size_t i = 0; i < np; ++i)
        {
            pts[i] = (double)cr->switch_points[i];
        }
    }
    printf(" | pred %-8s %-5s conf %.2f ", k_cls_short[o->pred], v >= 0 ? r->ch[v].name : "-",
           o->confidence);
    print_points(pts, np);
    printf(" | %s%s\n", o->class_ok && o->channel_ok ? "ok" : "MISS",
           o->n_err > 0 ? "" : (c->n_switch > 0 && o->channel_ok ? " (no points)" : ""));
}

/* --write: the case's INI, its CSV when missed, one results.tsv line. */
static void write_case(const args_t *a, const aenl_eval_case_t *c, const outcome_t *o, FILE *tsv)
{
    char path[1200];
    aenl_err_t err;
    aenl_err_clear(&err);
    (void)snprintf(path, sizeof(path), "%s/case_%04zu.ini", a->write_dir, c->index);
    if (aenl_eval_case_write_ini(c, path, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
    }
    if (!(o->class_ok && o->channel_ok))
    {
        aenl_sim_result_t res;
        memset(&res, 0, sizeof(res));
        res.n_samples = c->n_samples;
        res.n_channels = c->n_channels;
        res.names[0] = "t";
        for (size_t k = 0; k < c->n_channels; ++k)
        {
            res.names[k + 1] = c->names[k];
        }
        res.t = malloc(c->n_samples * sizeof(double));
        res.y = c->y;
        if (res.t != NULL)
        {
            for (size_t k = 0; k < c->n_samples; ++k)
            {
                res.t[k] = (double)k * c->run.dt;
            }
            (void)snprintf(path, sizeof(path), "%s/case_%04zu.csv", a->write_dir, c->index);
            if (aenl_sim_result_write_csv(&res, path, &err) != AENL_OK)
            {
                aenl_cli_error(k_cmd, "%s", err.msg);
            }
            free(res.t);
        }
    }
    if (tsv != NULL)
    {
        fprintf(tsv, "%zu\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%d\t%d\t%s\n", c->index,
                aenl_eval_variant_name(c->stratum.variant),
                c->model.type == AENL_SIM_AIRFOIL2DOF ? "airfoil2dof" : "section3dof",
                aenl_eval_dof_name(c->stratum.dof), aenl_eval_regime_name(c->stratum.regime),
                k_snr_name[c->stratum.snr_level], k_cls_short[o->truth],
                c->channel[0] ? c->channel : "-", k_cls_short[o->pred], o->class_ok, o->channel_ok,
                c->description);
    }
}

/* ---- classifier update cost ----------------------------------------------------------------- */

/* ρ(L) of white noise through the filter (impulse response until it has died out). */
static void noise_acf(const aenl_filter_t *proto, const uint16_t *lags, uint16_t n_lags,
                      aenl_real_t *rho)
{
    enum
    {
        N_IMP = 1 << 14
    };
    static double imp[N_IMP];
    aenl_filter_t f = *proto;
    aenl_real_t y = 0;
    double e = 0.0;
    size_t n = 0;
    aenl_filter_reset(&f);
    for (; n < N_IMP; ++n)
    {
        (void)aenl_filter_push(&f, n == 0 ? 1 : 0, &y);
        imp[n] = (double)y;
        e += imp[n] * imp[n];
    }
    for (uint16_t i = 0; i < n_lags; ++i)
    {
        double s = 0.0;
        for (size_t k = 0; k + lags[i] < n; ++k)
        {
            s += imp[k] * imp[k + lags[i]];
        }
        rho[i] = (aenl_real_t)(e > 0.0 ? s / e : 0.0);
    }
}

/** The classifier-update timing, taken on one case and printed with the summary. */
typedef struct timing
{
    int done;
    aenl_status_t status; /* of the timed updates */
    double ns;
    size_t index, samples;
    const char *channel;
    unsigned nodes, lags, order, used;
    aenl_class_t cls;
} timing_t;

/*
 * One classifier update, timed on the moments state the pipeline builds for a channel: its grid,
 * bandwidth and lags (symmetric pairs, direction split), the channel's samples through a 4th-order
 * low-pass at its pre-filter cutoff, the classifier at lag-expansion order 3 with the filtered
 * noise's correlation. Best of several rounds of repeated updates.
 */
static void time_update(const aenl_eval_case_t *c, const aenl_identify_channel_t *ch,
                        const double *y, timing_t *tm)
{
    aenl_moments_t *m = malloc(sizeof(*m));
    aenl_classifier_t *cls = malloc(sizeof(*cls));
    aenl_moments_cfg_t mc;
    aenl_classifier_cfg_t cc;
    aenl_filter_t f;
    int filtered = 0;
    memset(tm, 0, sizeof(*tm));
    tm->done = 1;
    tm->status = AENL_E_ARG;
    tm->index = c->index;
    tm->samples = c->n_samples;
    tm->channel = ch->name;
    if (m == NULL || cls == NULL)
    {
        free(m);
        free(cls);
        return;
    }
    memset(&mc, 0, sizeof(mc));
    mc.x_min = (aenl_real_t)ch->x_min;
    mc.x_max = (aenl_real_t)ch->x_max;
    mc.n_grid = ch->n_grid;
    mc.bandwidth = (aenl_real_t)ch->bandwidth;
    mc.n_lags = ch->n_lags;
    memcpy(mc.lags, ch->lags, sizeof(mc.lags));
    mc.forgetting = 1;
    mc.direction_split = 1;
    mc.symmetric = 1;
    aenl_classifier_cfg_default(&cc);
    cc.taylor_order = 3;
    if (ch->prefilter > 0.0 && ch->prefilter < 0.5)
    {
        const aenl_filter_cfg_t fc = {(aenl_real_t)ch->prefilter, 4};
        filtered = aenl_filter_init(&f, &fc) == AENL_OK;
    }
    if (filtered)
    {
        cc.use_noise_acf = 1;
        noise_acf(&f, mc.lags, mc.n_lags, cc.noise_acf);
    }
    tm->nodes = mc.n_grid;
    tm->lags = mc.n_lags;
    tm->order = cc.taylor_order;
    if (aenl_moments_init(m, &mc) == AENL_OK && aenl_classifier_init(cls, &cc) == AENL_OK)
    {
        for (size_t k = 0; k < c->n_samples; ++k)
        {
            aenl_real_t v = (aenl_real_t)y[k];
            if (filtered)
            {
                (void)aenl_filter_push(&f, v, &v);
            }
            (void)aenl_moments_push(m, v);
        }
        double best = HUGE_VAL;
        const int reps = 50;
        tm->status = AENL_OK;
        for (int round = 0; round < 5 && tm->status == AENL_OK; ++round)
        {
            const double t0 = aenl_now_s();
            for (int r = 0; r < reps && tm->status == AENL_OK; ++r)
            {
                tm->status = aenl_classifier_update(cls, m);
            }
            best = fmin(best, (aenl_now_s() - t0) / reps);
        }
        tm->ns = 1e9 * best;
        tm->used = aenl_classifier_result(cls)->n_nodes;
        tm->cls = aenl_classifier_result(cls)->cls;
    }
    free(m);
    free(cls);
}

static void print_timing(const timing_t *tm)
{
    printf("\nclassifier (core, host double, -O2):\n");
    if (!tm->done)
    {
        printf("  no freeplay/hysteresis case in this run: update not timed\n");
    }
    else if (tm->status != AENL_OK)
    {
        printf("  update not timed: %s (case %zu, %u nodes, %u lags, order %u)\n",
               aenl_status_str(tm->status), tm->index, tm->nodes, tm->lags, tm->order);
    }
    else
    {
        printf(
            "  one update (aenl_classifier_update): %.0f ns, on the pipeline's state of case %zu "
            "channel %s\n    (%u nodes, %u symmetric lags, direction split, order %u, %zu "
            "samples pushed; %u points used -> %s)\n",
            tm->ns, tm->index, tm->channel, tm->nodes, tm->lags, tm->order, tm->samples, tm->used,
            aenl_class_name(tm->cls));
    }
    printf("  sizeof(aenl_classifier_t) = %zu B, sizeof(aenl_moments_t) = %zu B (host capacities: "
           "%u classifier nodes)\n",
           sizeof(aenl_classifier_t), sizeof(aenl_moments_t), (unsigned)AENL_CLASSIFIER_MAX_NODES);
}

/* ---- report --------------------------------------------------------------------------------- */

static void print_confusion(const tally_t *t)
{
    for (unsigned l = 0; l < N_SNR; ++l)
    {
        if (t->cases[l] == 0)
        {
            continue;
        }
        printf("\nSNR %s: %zu cases, class accuracy %.1f %%, correct channel %.1f %%\n",
               k_snr_name[l], t->cases[l], pct(t->class_ok[l], t->cases[l]),
               pct(t->channel_ok[l], t->cases[l]));
        printf("  truth \\ predicted ");
        for (int p = 0; p < N_PRED; ++p)
        {
            printf("%9s", k_cls_short[p]);
        }
        printf("\n");
        for (int r = 0; r < N_TRUTH; ++r)
        {
            printf("  %-18s", k_cls_short[r + 1]);
            for (int p = 0; p < N_PRED; ++p)
            {
                printf("%9zu", t->conf[l][r][p]);
            }
            printf("\n");
        }
    }
}

static void print_summary(tally_t *t, int alone)
{
    printf("\nper SNR       class acc  goal   channel  goal | gap cases  no pts  n differs  "
           "points  median err  p90 err (x gap; goal median <= 0.10 at SNR 3)\n");
    size_t all_c = 0, all_ok = 0, all_ch = 0;
    for (unsigned l = 0; l < N_SNR; ++l)
    {
        if (t->cases[l] == 0)
        {
            continue;
        }
        const size_t ne = t->n_err[l];
        const double med = quantile(t->err[l], ne, 0.5), p90 = quantile(t->err[l], ne, 0.9);
        printf("  SNR %-4s    %6.1f %%  %s   %6.1f %%  >=95 | %9zu  %6zu  %9zu  %6zu  %10.3f  "
               "%7.3f\n",
               k_snr_name[l], pct(t->class_ok[l], t->cases[l]), l == 3 ? ">=90" : ">=97",
               pct(t->channel_ok[l], t->cases[l]), t->gap_cases[l], t->no_points[l],
               t->count_differs[l], ne, med, p90);
        all_c += t->cases[l];
        all_ok += t->class_ok[l];
        all_ch += t->channel_ok[l];
    }
    printf("  all         %6.1f %%         %6.1f %%\n", pct(all_ok, all_c), pct(all_ch, all_c));
    if (alone)
    {
        printf(
            "\neach analysis alone (class / channel)   SNR inf        SNR 10         SNR 3       "
            "   SNR 2\n");
    }
    for (int w = 0; alone && w < (t->n_model > 0 ? 3 : 2); ++w)
    {
        printf("  %-36s", w == 0   ? "core classifier (moments, onboard)"
                          : w == 1 ? "restoring-force regression"
                                   : "the record alone (no model)");
        for (unsigned l = 0; l < N_SNR; ++l)
        {
            printf(" %5.1f / %5.1f", pct(t->alone[w][l][0], t->cases[l]),
                   pct(t->alone[w][l][1], t->cases[l]));
        }
        printf("\n");
    }
    printf("\nper regime    cases  class  channel  Brier score of the confidence\n");
    for (int r = 0; r < (int)AENL_EVAL_N_REGIMES; ++r)
    {
        const size_t *b = t->by_regime[r];
        if (b[0] == 0)
        {
            continue; /* --regime left it out */
        }
        printf("  %-10s  %5zu  %5.1f %%  %5.1f %%  %6.3f\n",
               aenl_eval_regime_name((aenl_eval_regime_t)r), b[0], pct(b[1], b[0]), pct(b[2], b[0]),
               t->brier[r] / (double)b[0]);
    }
    printf("per model\n");
    for (int m = 0; m < 2; ++m)
    {
        const size_t *b = t->by_model[m];
        printf("  %-10s  %5zu  %5.1f %%  %5.1f %%\n", m == 0 ? "airfoil2dof" : "section3dof", b[0],
               pct(b[1], b[0]), pct(b[2], b[0]));
    }
    printf("per variant x regime (cases: class ok / channel ok)\n  %-11s", "");
    for (int r = 0; r < (int)AENL_EVAL_N_REGIMES; ++r)
    {
        printf("%18s", aenl_eval_regime_name((aenl_eval_regime_t)r));
    }
    printf("\n");
    for (int v = 0; v < (int)AENL_EVAL_N_VARIANTS; ++v)
    {
        printf("  %-11s", aenl_eval_variant_name((aenl_eval_variant_t)v));
        for (int r = 0; r < (int)AENL_EVAL_N_REGIMES; ++r)
        {
            const size_t *b = t->by_cell[v][r];
            if (b[0] == 0)
            {
                printf("%18s", "-");
            }
            else
            {
                char cell[40];
                (void)snprintf(cell, sizeof(cell), "%zu: %zu / %zu", b[0], b[1], b[2]);
                printf("%18s", cell);
            }
        }
        printf("\n");
    }
}

/* How often a verdict given with a confidence is right (class and channel), and the Brier score
 * (mean squared difference between the confidence and being right: 0 perfect, 0.25 for a
 * confidence of 0.5 on everything). */
static void print_reliability(const tally_t *t)
{
    double brier = 0.0;
    for (int r = 0; r < (int)AENL_EVAL_N_REGIMES; ++r)
    {
        brier += t->brier[r];
    }
    printf("\nconfidence of the verdict vs right (class and channel); Brier score %.3f\n",
           t->n > 0 ? brier / (double)t->n : (double)NAN);
    printf("  confidence      verdicts  right     mean confidence\n");
    for (int b = 0; b < N_BANDS; ++b)
    {
        char band[32];
        (void)snprintf(band, sizeof(band), "[%.2f, %.2f%c", k_band[b], fmin(k_band[b + 1], 1.0),
                       b + 1 == N_BANDS ? ']' : ')');
        printf("  %-14s  %8zu  %5.1f %%  %6.3f\n", band, t->band_n[b],
               pct(t->band_ok[b], t->band_n[b]),
               t->band_n[b] > 0 ? t->band_conf[b] / (double)t->band_n[b] : (double)NAN);
    }
}

/* The model-based test of `identify --model` on case c's first n rows: a diagnosis against the
 * case's own model with its law made linear, under the case's conditions. */
static aenl_status_t model_test(const aenl_eval_case_t *c, size_t n, int unknown_gusts,
                                aenl_identify_result_t *res, aenl_err_t *err)
{
    aenl_sim_model_t base = c->model;
    aenl_sim_run_t run = c->run;
    if (unknown_gusts)
    {
        run.turb_seed += UNKNOWN_GUST_SEED_STEP;
    }
    if (c->stratum.dof >= 0)
    {
        memset(&base.law[c->stratum.dof], 0, sizeof(base.law[c->stratum.dof]));
        base.law[c->stratum.dof].kind = AENL_SIM_LAW_LINEAR;
    }
    const char *names[1 + 3] = {"t", NULL, NULL, NULL};
    for (size_t k = 0; k < c->n_channels && k < 3u; ++k)
    {
        names[k + 1u] = c->names[k];
    }
    aenl_table_t tab;
    aenl_status_t st = aenl_table_alloc(&tab, n, c->n_channels + 1u, names, err);
    if (st != AENL_OK)
    {
        return st;
    }
    for (size_t i = 0; i < n; ++i)
    {
        tab.data[i] = (double)i * c->run.dt;
    }
    for (size_t k = 0; k < c->n_channels; ++k)
    {
        memcpy(tab.data + (k + 1u) * n, c->cols[k], n * sizeof(double));
    }
    st = aenl_identify_model_test(res, &tab, &base, &run, NULL, NULL, err);
    aenl_table_free(&tab);
    return st;
}

/* Score a verdict of the test on the record alone: class (undetermined counts as wrong, in the
 * column of class 0), channel, switching points of the named channel as in score(). */
static void score_test(const aenl_eval_case_t *c, const aenl_nlt_result_t *r, outcome_t *o)
{
    const long v = r != NULL ? r->verdict : -1;
    if (!score_verdict(c, r != NULL, r != NULL ? (int)r->verdict_class : 0, v,
                       r != NULL ? r->confidence : 0.0, o))
    {
        return;
    }
    const aenl_nlt_channel_t *ch = &r->ch[v];
    if (ch->n_points == 0 || r->undetermined)
    {
        o->no_points = 1;
        return;
    }
    o->count_differs = ch->n_points != c->n_switch;
    for (size_t i = 0; i < c->n_switch; ++i)
    {
        double best = HUGE_VAL;
        for (size_t j = 0; j < ch->n_points; ++j)
        {
            best = fmin(best, fabs(ch->points[j] - c->switch_points[i]));
        }
        o->err[o->n_err++] = best / c->gap;
    }
}

/* Case i of the suite into c (1), or not generated (0, counted and said) or out of memory (-1). */
static int make_case(const args_t *a, size_t i, tally_t *t, aenl_eval_case_t *c)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    const double t0 = aenl_now_s();
    const aenl_status_t st = aenl_eval_case_make_with(a->seed, i, &a->sim, c, &err);
    t->t_gen += aenl_now_s() - t0;
    if (st != AENL_OK)
    {
        ++t->gen_failures;
        printf("  case %zu not generated: %s\n", i, err.msg);
        return st == AENL_E_IO ? -1 : 0;
    }
    t->rejections += c->attempt;
    t->cases_rejected += c->attempt > 0;
    return 1;
}

/* One case through identify --method test. */
static int run_case_test(args_t *a, size_t i, tally_t *t)
{
    aenl_eval_case_t c;
    aenl_err_t err;
    const int made = make_case(a, i, t, &c);
    if (made <= 0)
    {
        return made;
    }
    aenl_err_clear(&err);
    const size_t n = a->rows > 0 && (size_t)a->rows < c.n_samples ? (size_t)a->rows : c.n_samples;
    const size_t nc = c.n_channels;
    aenl_nlt_opts_t opts;
    aenl_nlt_opts_default(&opts);
    opts.impulsive = a->impulsive && c.stratum.regime == AENL_EVAL_DECAY;
    aenl_nlt_result_t res;
    aenl_err_clear(&err);
    double t0 = aenl_now_s();
    const aenl_status_t sti = aenl_nlt_run_columns(c.cols, n, nc, &opts, &res, &err);
    t->t_id += aenl_now_s() - t0;
    a->samples += n * nc;
    if (sti != AENL_OK)
    {
        ++t->id_failures;
        printf("  case %zu: identify --method test failed: %s\n", i, err.msg);
    }
    outcome_t o;
    score_test(&c, sti == AENL_OK ? &res : NULL, &o);
    const int rc = tally_add(t, &o);
    if (a->verbose)
    {
        printf("  %4zu %-11s %-11s %-6s %-10s SNR %-3s truth %-10s %-6s -> %-12s %-6s conf %.3f "
               "p %.2e imp %zu%s%s\n",
               i, aenl_eval_variant_name(c.stratum.variant),
               c.stratum.model == 0 ? "airfoil2dof" : "section3dof",
               aenl_eval_dof_name(c.stratum.dof), aenl_eval_regime_name(c.stratum.regime),
               k_snr_name[c.stratum.snr_level], aenl_class_name(c.cls),
               c.channel_index >= 0 ? c.names[c.channel_index] : "-",
               sti == AENL_OK ? aenl_nlt_class_name(res.verdict_class, res.undetermined) : "failed",
               sti == AENL_OK && res.verdict >= 0 ? c.names[res.verdict] : "-", o.confidence,
               sti == AENL_OK && res.verdict >= 0 ? res.ch[res.verdict].p : 1.0,
               sti == AENL_OK ? res.n_impulses : 0u, sti == AENL_OK && res.jumps ? " jumps" : "",
               o.class_ok && o.channel_ok ? "" : "  MISS");
    }
    aenl_eval_case_free(&c);
    return rc;
}

static int run_case(const args_t *a, size_t i, tally_t *t, FILE *tsv, timing_t *tm)
{
    aenl_eval_case_t c;
    aenl_err_t err;
    const int made = make_case(a, i, t, &c);
    if (made <= 0)
    {
        return made;
    }
    aenl_err_clear(&err);
    aenl_identify_source_t src;
    aenl_identify_arrays_t ctx;
    aenl_identify_opts_t opts;
    aenl_identify_result_t res;
    aenl_identify_opts_default(&opts);
    const size_t n = a->rows > 0 && (size_t)a->rows < c.n_samples ? (size_t)a->rows : c.n_samples;
    aenl_identify_arrays_source(&src, &ctx, c.cols, c.names, c.n_channels, n);
    aenl_err_clear(&err);
    double t0 = aenl_now_s();
    const aenl_status_t sti = aenl_identify_run(&src, &opts, &res, &err);
    t->t_id += aenl_now_s() - t0;
    outcome_t o;
    if (a->model && sti == AENL_OK)
    {
        score(&c, &res, &o); /* the record alone */
        t->alone[2][c.stratum.snr_level][0] += (size_t)o.class_ok;
        t->alone[2][c.stratum.snr_level][1] += (size_t)o.channel_ok;
        t0 = aenl_now_s();
        ++t->n_model;
        if (model_test(&c, n, a->unknown_gusts, &res, &err) != AENL_OK)
        {
            ++t->model_failures;
            printf("  case %zu: the model-based test failed: %s\n", i, err.msg);
        }
        else if (res.model.base_test >= 0)
        {
            const aenl_diagnose_sumtest_t *bs = &res.model.base_sum;
            const char *says = res.model.base_test == 1 ? "linear" : "the record's verdict stands";
            if (bs->n_rep == 0u)
            {
                printf("  case %zu (%s): the baseline reproduces the record (gap %.3g, its runs "
                       "all alike; the record alone: %s): %s\n",
                       i, aenl_class_name(c.cls), res.model.gap_before,
                       aenl_class_name(res.model.data_class), says);
            }
            else
            {
                printf("  case %zu (%s): the baseline fits (gap %.3g); its summaries' distance^2 "
                       "%.3g for %zu, p %.3g (the record alone: %s): %s\n",
                       i, aenl_class_name(c.cls), res.model.gap_before, bs->d2, bs->d, bs->p,
                       aenl_class_name(res.model.data_class), says);
            }
        }
        else if (res.model.effect2 != AENL_DIAGNOSE_NONE)
        {
            ++t->model_second;
            printf("  case %zu: a second effect named: %s in %s (the suite's cases have one law)\n",
                   i, aenl_diagnose_effect_name(res.model.effect2),
                   aenl_diagnose_dof_name(res.model.dof2));
        }
        t->t_model += aenl_now_s() - t0;
    }
    if (sti != AENL_OK)
    {
        ++t->id_failures;
        printf("  case %zu: identify failed: %s\n", i, err.msg);
    }
    score(&c, sti == AENL_OK ? &res : NULL, &o);
    score_alone(&c, sti == AENL_OK ? &res : NULL, 0, t);
    score_alone(&c, sti == AENL_OK ? &res : NULL, 1, t);
    int rc = tally_add(t, &o);
    if (a->verbose)
    {
        print_verbose(&c, sti == AENL_OK ? &res : NULL, &o);
    }
    if (a->write_dir != NULL)
    {
        write_case(a, &c, &o, tsv);
    }
    /* The update cost: on the first gap case, its true channel (the pipeline's state). */
    if (!tm->done && sti == AENL_OK && c.n_switch > 0)
    {
        time_update(&c, &res.ch[c.channel_index], c.cols[c.channel_index], tm);
    }
    if (sti == AENL_OK)
    {
        aenl_identify_free(&res);
    }
    aenl_eval_case_free(&c);
    return rc;
}

int aenl_bench_identify(int argc, char **argv)
{
    args_t a;
    tally_t t;
    FILE *tsv = NULL;
    timing_t tm;
    int rc = AENL_EXIT_OK;
    const int pr = parse_args(argc, argv, &a);
    if (pr != 0)
    {
        return pr > 0 ? AENL_EXIT_OK : AENL_EXIT_USAGE;
    }
    if (a.method_test && (a.model || a.write_dir != NULL))
    {
        aenl_cli_error(k_cmd, "--method test does not combine with --model or --write");
        return AENL_EXIT_USAGE;
    }
    if (a.impulsive && !a.method_test)
    {
        aenl_cli_error(k_cmd, "--impulsive needs --method test");
        return AENL_EXIT_USAGE;
    }
    if (a.write_dir != NULL)
    {
        char path[1200];
        (void)mkdir(a.write_dir, 0777);
        (void)snprintf(path, sizeof(path), "%s/results.tsv", a.write_dir);
        if ((tsv = fopen(path, "w")) == NULL)
        {
            aenl_cli_error(k_cmd, "cannot write %s", path);
            return AENL_EXIT_USAGE;
        }
        fprintf(tsv, "index\tvariant\tmodel\tdof\tregime\tsnr\ttruth\tchannel\tpredicted\tclass_ok"
                     "\tchannel_ok\tdescription\n");
    }
    memset(&t, 0, sizeof(t));
    memset(&tm, 0, sizeof(tm));
    if (a.method_test)
    {
        k_cls_short[0] = "undet";
    }
    printf("identification evaluation suite: %ld cases, seed %llu (aenl_evalsuite.h); %s, "
           "%s\n",
           a.cases, a.seed,
           a.method_test ? "identify --method test (aenl_nlt_run)" : "pipeline aenl_identify_run",
           a.impulsive ? "the decays (kick trains) declared driven by impulses (--impulsive)"
                       : "default options");
    if (a.regime >= 0 || a.rows > 0 || a.model)
    {
        if (a.regime >= 0)
        {
            printf("only the %s cases", aenl_eval_regime_name((aenl_eval_regime_t)a.regime));
        }
        if (a.rows > 0)
        {
            printf("%seach record's first %ld rows", a.regime >= 0 ? ", " : "", a.rows);
        }
        printf("%s%s\n", a.model ? "; verdicts from the model-based test (identify --model)" : "",
               a.model ? (a.unknown_gusts ? ", given another turbulence seed than the record's"
                                          : ", given the record's turbulence seed")
                       : "");
    }
    if (a.sim.rk4 || a.sim.spectrum == AENL_SIM_GUST_DRYDEN)
    {
        printf("records from another simulator:");
        if (a.sim.rk4)
        {
            printf(" naive fixed-step RK4 (%d steps a sample, no event location, no sticking)",
                   AENL_EVAL_RK4_STEPS);
        }
        if (a.sim.spectrum == AENL_SIM_GUST_DRYDEN)
        {
            printf("%s Dryden gust spectrum", a.sim.rk4 ? ";" : "");
        }
        printf("\n");
    }
    (void)fflush(stdout);
    const double t_start = aenl_now_s();
    aenl_cli_bar_t bar; /* with a line per case (--verbose), those lines show the progress */
    aenl_cli_bar_begin(&bar, "bench identify", "cases");
    bar.on = bar.on && !a.verbose;
    for (long i = a.from; i < a.cases; ++i)
    {
        aenl_cli_bar_update(&bar, (size_t)(i - a.from), (size_t)(a.cases - a.from));
        aenl_eval_stratum_t so;
        aenl_eval_stratum_of((size_t)i, &so);
        if (a.regime >= 0 && (int)so.regime != a.regime)
        {
            continue;
        }
        if ((a.method_test ? run_case_test(&a, (size_t)i, &t)
                           : run_case(&a, (size_t)i, &t, tsv, &tm)) != 0)
        {
            aenl_cli_error(k_cmd, "out of memory");
            rc = AENL_EXIT_FAIL;
            break;
        }
        (void)fflush(stdout);
    }
    aenl_cli_bar_end(&bar);
    const double wall = aenl_now_s() - t_start;
    if (tsv != NULL && fclose(tsv) != 0)
    {
        aenl_cli_error(k_cmd, "error writing results.tsv");
    }
    print_confusion(&t);
    print_summary(&t, !a.method_test);
    print_reliability(&t);
    printf("\ngeneration: %zu cases, %zu rejected attempts (in %zu cases), %zu not generated; "
           "%.2f s per case\n",
           t.n, t.rejections, t.cases_rejected, t.gen_failures,
           t.n > 0 ? t.t_gen / (double)t.n : 0.0);
    printf("identification: %.2f s per case, %zu failures\n", t.n > 0 ? t.t_id / (double)t.n : 0.0,
           t.id_failures);
    if (t.n_model > 0)
    {
        printf("model-based test: %.1f s per case, %zu failures, a second effect named in %zu "
               "(spurious: one law a case)\n",
               t.t_model / (double)t.n_model, t.model_failures, t.model_second);
    }
    if (a.method_test)
    {
        printf("identify --method test: %.3g s per million values (samples x channels), %.3g s "
               "for a 20 000-sample 3-channel record at that rate (--jobs %u)\n",
               a.samples > 0 ? t.t_id / (double)a.samples * 1e6 : 0.0,
               a.samples > 0 ? t.t_id / (double)a.samples * 60000.0 : 0.0, aenl_jobs());
        printf("\nwall time %.1f s\n", wall);
        for (unsigned l = 0; l < N_SNR; ++l)
        {
            free(t.err[l]);
        }
        return rc;
    }
    print_timing(&tm);
    printf("float32 core (aenl_classifier_bench_f32, default aenl_config.h):\n");
    (void)fflush(stdout);
    if (aenl_bench_run_sibling("aenl_classifier_bench_f32", NULL, 0) != AENL_EXIT_OK)
    {
        printf("  (not available)\n");
    }
    printf("\nwall time %.1f s\n", wall);
    for (unsigned l = 0; l < N_SNR; ++l)
    {
        free(t.err[l]);
    }
    return rc;
}
