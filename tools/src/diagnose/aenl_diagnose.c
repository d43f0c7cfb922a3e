/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose.c
 * @brief The diagnosis workflow: simulate the baseline under the measured conditions, measure the
 *        gap and its noise floor, calibrate every candidate effect by simulation (coarse grid,
 *        then Nelder-Mead on the gap, common random numbers), choose with a parameter penalty,
 *        and build the updated model (docs/diagnose.md).
 */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_diagnose_internal.h"
#include "aenl_tools/aenl_clock.h"
#include "aenl_tools/aenl_parallel.h"
#include "aenl_tools/aenl_rng.h"

#define N_CH_MAX AENL_SIM_MAX_Q
#define N_FAM    AENL_DIAGNOSE_N_FAMILY

/* Seeds of replicate r > 0: offsets that keep them apart from the main ones (r = 0). */
#define TURB_SEED_STEP  7919u
#define NOISE_SEED_STEP 104729u

/* Candidates whose replicate floor enters the common yardstick of the choice. */
#define N_FLOOR_CAND 3u
/* The nominal noise (a fraction of each channel's std) that measures the gap's degrees of
 * freedom where the runs do not differ (nominal_rv). */
#define NOMINAL_NOISE 1e-3

/* The level at which the largest excursion of a record of n samples tells it is not a
 * stationary Gaussian record (motion_scale): such a record passes t stds anywhere with
 * probability at most 2 n exp(-t^2 / 2) (the union of its samples' tails), STATIONARY_LEVEL at
 * t = sqrt(2 ln(2 n / STATIONARY_LEVEL)): 5.3 stds at 6 000 samples, 5.8 at 10^5. */
#define STATIONARY_LEVEL 0.01

/* Runaway bound of every candidate simulation, in measured stds and in multiples of the
 * record's largest excursion, whichever is further (see ctx_t.bound). */
#define RUNAWAY_LIMIT 20.0
#define RUNAWAY_REACH 2.0
/* ... and in integration steps per output sample: a model that needs more is too stiff to
 * compare (a perturbed softening spring settled at a second equilibrium once took 33 million
 * steps, 1650 a sample, for one record of the summary fit), and costs as much as a runaway. */
#define RUNAWAY_STEPS 200.0

void aenl_diagnose_opts_default(aenl_diagnose_opts_t *o)
{
    memset(o, 0, sizeof(*o));
    o->n_replicates = 3;
    o->penalty = 2.0;
    o->none_ratio = 2.0;
    o->report_ratio = 3.0;
    o->n_refine = 4;
    o->max_evals = 40;
    o->summary_records = 64;
    o->noise_seed = 1;
    o->verbose = 0;
}

const char *aenl_diagnose_effect_name(aenl_diagnose_effect_t e)
{
    switch (e)
    {
        case AENL_DIAGNOSE_FREEPLAY:
            return "freeplay";
        case AENL_DIAGNOSE_HYSTERESIS:
            return "hysteresis";
        case AENL_DIAGNOSE_POLYNOMIAL:
            return "polynomial";
        case AENL_DIAGNOSE_PRELOAD:
            return "preload";
        case AENL_DIAGNOSE_NONE:
        default:
            return "none";
    }
}

const char *aenl_diagnose_dof_name(aenl_sim_dof_t d)
{
    switch (d)
    {
        case AENL_SIM_DOF_PLUNGE:
            return "plunge";
        case AENL_SIM_DOF_FLAP:
            return "flap";
        case AENL_SIM_DOF_PITCH:
        default:
            return "pitch";
    }
}

const char *aenl_diagnose_family_name(aenl_diagnose_family_t f)
{
    switch (f)
    {
        case AENL_DIAGNOSE_MEAN:
            return "conditional_mean";
        case AENL_DIAGNOSE_STD:
            return "conditional_std";
        case AENL_DIAGNOSE_SPECTRUM:
            return "spectrum";
        case AENL_DIAGNOSE_AMPLITUDE:
        default:
            return "amplitude";
    }
}

const char *const *aenl_diagnose_channel_names(aenl_sim_type_t type, size_t *n)
{
    static const char *const names2[] = {"alpha", "xi"};
    static const char *const names3[] = {"h", "alpha", "beta"};
    if (type == AENL_SIM_AIRFOIL2DOF)
    {
        *n = 2;
        return names2;
    }
    *n = 3;
    return names3;
}

size_t aenl_diagnose_dof_channel(aenl_sim_type_t type, aenl_sim_dof_t dof)
{
    if (type == AENL_SIM_AIRFOIL2DOF)
    {
        return dof == AENL_SIM_DOF_PLUNGE ? 1u : 0u;
    }
    return dof == AENL_SIM_DOF_PLUNGE ? 0u : (dof == AENL_SIM_DOF_PITCH ? 1u : 2u);
}

/* ---- simulation of one model under the record's conditions ------------------------------- */

typedef struct
{
    aenl_sim_run_t run; /* the record's conditions, noise off */
    size_t n, n_ch;
    aenl_diagnose_result_t *res; /* settings and measured signatures */
    uint64_t noise_seed;
    unsigned n_sims;
    int verbose;
    const aenl_progress_t *progress;
    size_t step, steps; /* stages done of the search's (progress) */
    /* Runaway bound of every candidate simulation per channel: RUNAWAY_LIMIT times the larger
     * of the measured std and mean, from zero, or RUNAWAY_REACH times the record's largest
     * excursion from its mean where that is further (a long free decay starts many stds out:
     * a release 20 stds out would otherwise be taken for a runaway). Runaway models can become very
     * stiff (a diverging flutter mode driving a hardening spring) and their full runs would
     * dominate the cost; the simulator stops them there, and their signatures are invalid (every
     * difference capped), as are those of models that diverge. */
    double bound[N_CH_MAX];
    double reach[N_CH_MAX]; /* the record's largest excursion from its mean, per channel */
    /* 1: every model simulated starts from its own initial state fitted to the record's start
     * (own_start): a free decay released from a state nobody measured. */
    int fit_initial;
} ctx_t;

/* The record's conditions with the runaway bounds: every simulation stops where a model runs
 * away (see ctx_t.bound) or grows too stiff (RUNAWAY_STEPS), those of the summaries too, which
 * would otherwise integrate a softening spring's runaway to the record's end. */
static aenl_sim_run_t bounded_run(const ctx_t *x)
{
    aenl_sim_run_t run = x->run;
    memcpy(run.bound, x->bound, sizeof(run.bound));
    run.max_steps_per_sample = RUNAWAY_STEPS;
    return run;
}

/* m, started from its own initial state fitted to the record (x->fit_initial), into *out, with
 * that fit's standard errors into *info (NULL: not wanted). The release is not known, so each
 * model is compared from the release that suits it best over the record's first period: a law
 * changes the first cycle too, and the baseline's start would leave a model with the law a
 * misfit that is the start's, not the law's. Where the fit fails (the window cannot be simulated
 * from m), m's own state stands. Only out-of-memory is an error. */
static aenl_status_t own_start(const ctx_t *x, const aenl_sim_model_t *m, aenl_sim_model_t *out,
                               aenl_diagnose_initial_t *info, aenl_err_t *err)
{
    *out = *m;
    if (!x->fit_initial)
    {
        return AENL_OK;
    }
    const aenl_sim_run_t run = bounded_run(x);
    aenl_diagnose_initial_t fitted;
    aenl_err_t e;
    aenl_err_clear(&e);
    const aenl_status_t st =
        aenl_diagnose_initial_fit(m, &run, x->res->y_meas, x->n, x->res->chan, out, &fitted, &e);
    if (st == AENL_E_DIM)
    {
        aenl_err_set(err, "%s", e.msg);
        return st;
    }
    if (st != AENL_OK)
    {
        *out = *m;
    }
    else if (info != NULL)
    {
        *info = fitted;
    }
    return AENL_OK;
}

/* Add the measurement noise of replicate `rep` to the clean run r (in place) and take its
 * signatures; y (n_ch * n) and psd (n_ch * n_bins) may be NULL. */
static aenl_status_t noisy_sig(ctx_t *x, aenl_sim_result_t *r, unsigned rep,
                               aenl_diagnose_sig_t *sig, double *y, double *psd, aenl_err_t *err)
{
    aenl_rng_t rng;
    aenl_rng_seed(&rng, x->noise_seed + (uint64_t)rep * NOISE_SEED_STEP);
    aenl_status_t out = AENL_OK;
    for (size_t c = 0; c < x->n_ch && out == AENL_OK; ++c)
    {
        double *ch = r->y + c * r->n_samples;
        const double sd = x->res->chan[c].noise_sd;
        for (size_t i = 0; i < x->n; ++i)
        {
            ch[i] += sd * aenl_rng_gauss(&rng);
        }
        out = aenl_diagnose_signature(ch, x->n, &x->res->chan[c], &sig[c],
                                      psd ? psd + c * x->res->n_bins : NULL, err);
        if (y != NULL)
        {
            memcpy(y + c * x->n, ch, x->n * sizeof(double));
        }
    }
    return out;
}

/* Simulate `m` with the excitation seeds of replicate `rep_exc` (the clean run in *r). 1: a run
 * of the record's length; 0: it cannot be simulated (diverges, bad parameters: r holds nothing);
 * -1: out of memory (err set). */
static int sim_clean(ctx_t *x, const aenl_sim_model_t *m, unsigned rep_exc, aenl_sim_result_t *r,
                     aenl_err_t *err)
{
    aenl_sim_run_t run = bounded_run(x);
    run.turb_seed = x->run.turb_seed + (uint64_t)rep_exc * TURB_SEED_STEP;
    aenl_err_t e;
    aenl_err_clear(&e);
    x->n_sims++;
    aenl_sim_model_t own;
    if (own_start(x, m, &own, NULL, err) != AENL_OK)
    {
        return -1;
    }
    const aenl_status_t st = aenl_sim_simulate(&own, &run, r, &e);
    if (st == AENL_E_DIM)
    {
        aenl_err_set(err, "%s", e.msg);
        return -1;
    }
    if (st != AENL_OK || r->n_samples < x->n)
    {
        aenl_sim_result_free(r);
        return 0;
    }
    return 1;
}

/* Simulate `m` with the seeds of replicate `rep`, add the measured noise, take signatures.
 * A model that cannot be simulated (diverges, bad parameters) gives invalid signatures; only
 * out-of-memory is an error. y (n_ch * n) and psd (n_ch * n_bins) may be NULL. */
static aenl_status_t sim_sig(ctx_t *x, const aenl_sim_model_t *m, unsigned rep,
                             aenl_diagnose_sig_t *sig, double *y, double *psd, aenl_err_t *err)
{
    for (size_t c = 0; c < x->n_ch; ++c)
    {
        memset(&sig[c], 0, sizeof(sig[c]));
    }
    aenl_sim_result_t r;
    const int ok = sim_clean(x, m, rep, &r, err);
    if (ok < 0)
    {
        return AENL_E_DIM;
    }
    if (ok == 0)
    {
        if (y != NULL)
        {
            for (size_t i = 0; i < x->n_ch * x->n; ++i)
            {
                y[i] = (double)NAN;
            }
        }
        return AENL_OK;
    }
    const aenl_status_t out = noisy_sig(x, &r, rep, sig, y, psd, err);
    aenl_sim_result_free(&r);
    return out;
}

/* Gap of signatures b against a: per channel (ch may be NULL), families (fam may be NULL). */
static double gap_of(const ctx_t *x, const aenl_diagnose_sig_t *a, const aenl_diagnose_sig_t *b,
                     double *ch, double fam[][N_FAM])
{
    double tot = 0.0;
    for (size_t c = 0; c < x->n_ch; ++c)
    {
        double f[N_FAM];
        const double g = aenl_diagnose_distance(&x->res->chan[c], &a[c], &b[c], f);
        if (ch != NULL)
        {
            ch[c] = g;
        }
        if (fam != NULL)
        {
            memcpy(fam[c], f, sizeof(f));
        }
        tot += g * g;
    }
    return sqrt(tot / (double)x->n_ch);
}

/* Replicate floor of a model: main signatures `main_sig` plus n_rep replicates; the floor of
 * every gap is the RMS over all pairs of runs that stayed bounded. A run that diverges differs
 * from every other by the cap, which measures the divergence, not the noise: the share of runs
 * that stayed bounded is kept apart (`bounded`). Per-element floors (elem, NULL to skip) for the
 * bands. */
typedef struct
{
    double ch[N_CH_MAX + 1]; /* per channel, [n_ch] total */
    double fam[N_CH_MAX][N_FAM];
    double bounded;     /* share of the runs with every channel's signature valid */
    double same;        /* total floor of runs that share the main run's excitation and differ in
                           their noise only (the total floor when nothing else is random) */
    double rv, rv_same; /* relative variance of the pair gaps squared, of the two
                           floors; NAN when not determined */
} floor_t;

double aenl_diagnose_rel_var(double s2, double s4, size_t n_pair, size_t n_run)
{
    if (n_pair < 2u || !(s2 > 0.0))
    {
        return (double)NAN;
    }
    const double np = (double)n_pair, m = s2 / np;
    const double v = fmax(s4 / np - m * m, 0.0) * np / (np - 1.0);
    /* of the other pairs, 2 (n_run - 2) share a run with a given one */
    const double rho =
        n_pair == n_run * (n_run - 1u) / 2u ? 0.25 * 2.0 * (double)(n_run - 2u) / (np - 1.0) : 0.0;
    return v / (1.0 - rho) / (m * m);
}

/* Adds a floor's determined relative variances to the sums rv (and counts n) of the two scales:
 * [0] other excitation, [1] the noise alone. */
static void pool_rv(const floor_t *fl, double rv[2], size_t n[2])
{
    const double v[2] = {fl->rv, fl->rv_same};
    for (int k = 0; k < 2; ++k)
    {
        rv[k] += isfinite(v[k]) ? v[k] : 0.0;
        n[k] += isfinite(v[k]) ? 1u : 0u;
    }
}

/* 1 when every channel of a run's signatures is valid (the run did not diverge). */
static int run_bounded(const aenl_diagnose_sig_t *sig, size_t n_ch)
{
    int ok = 1;
    for (size_t c = 0; c < n_ch; ++c)
    {
        ok = ok && sig[c].valid;
    }
    return ok;
}

/* Floor of the runs that share the main run's excitation (replicate 0's turbulence) and differ
 * in their measurement noise only: the main signatures against n_rep noisy copies of one clean
 * run, RMS over the pairs that stayed bounded (no pair: 0). */
static aenl_status_t floor_same(ctx_t *x, const aenl_sim_model_t *m,
                                const aenl_diagnose_sig_t *main_sig, unsigned n_rep, double *out,
                                double *rv, aenl_err_t *err)
{
    *out = 0.0;
    *rv = (double)NAN;
    aenl_sim_result_t r;
    const int ok = sim_clean(x, m, 0u, &r, err);
    if (ok <= 0)
    {
        return ok < 0 ? AENL_E_DIM : AENL_OK;
    }
    const size_t n_run = (size_t)n_rep + 1u, len = x->n_ch * r.n_samples;
    aenl_diagnose_sig_t *s = malloc(n_run * x->n_ch * sizeof(*s));
    double *clean = malloc(len * sizeof(double));
    if (s == NULL || clean == NULL)
    {
        free(s);
        free(clean);
        aenl_sim_result_free(&r);
        aenl_err_set(err, "out of memory (replicates)");
        return AENL_E_DIM;
    }
    memcpy(clean, r.y, len * sizeof(double));
    memcpy(s, main_sig, x->n_ch * sizeof(*s));
    aenl_status_t st = AENL_OK;
    for (unsigned k = 1; k <= n_rep && st == AENL_OK; ++k)
    {
        memcpy(r.y, clean, len * sizeof(double));
        st = noisy_sig(x, &r, k, s + (size_t)k * x->n_ch, NULL, NULL, err);
    }
    double sum = 0.0, sum4 = 0.0;
    size_t n_pair = 0;
    for (size_t i = 0; i < n_run && st == AENL_OK; ++i)
    {
        for (size_t j = i + 1u; j < n_run; ++j)
        {
            if (run_bounded(s + i * x->n_ch, x->n_ch) && run_bounded(s + j * x->n_ch, x->n_ch))
            {
                const double g = gap_of(x, s + i * x->n_ch, s + j * x->n_ch, NULL, NULL);
                sum += g * g;
                sum4 += g * g * g * g;
                n_pair++;
            }
        }
    }
    *out = n_pair > 0u ? sqrt(sum / (double)n_pair) : 0.0;
    *rv = aenl_diagnose_rel_var(sum, sum4, n_pair, n_run);
    free(s);
    free(clean);
    aenl_sim_result_free(&r);
    return st;
}

/* Relative variance of the pair gaps squared where no two runs differ (no noise to add, no
 * turbulence): measured over runs of model m given a nominal noise, NOMINAL_NOISE of each
 * channel's std. 2 / M counts the gap's independent components, mostly a property of the
 * signatures' structure (their bins, lags, bands); M grows slowly with the noise's size as more
 * of the elements become the noise's (a 2-DOF decay in test_diagnose: about 8 at 0.1 %, 22 at
 * 3 %), so the nominal noise is small. NAN when not determined. */
static aenl_status_t nominal_rv(ctx_t *x, const aenl_sim_model_t *m, unsigned n_rep, double *rv,
                                aenl_err_t *err)
{
    *rv = (double)NAN;
    aenl_diagnose_sig_t *s0 = malloc(x->n_ch * sizeof(*s0));
    if (s0 == NULL)
    {
        aenl_err_set(err, "out of memory (signatures)");
        return AENL_E_DIM;
    }
    /* The shared settings are changed for a moment: this runs on the calling thread and no batch
     * of tasks (which read them through their copies of x) runs meanwhile. */
    double saved[N_CH_MAX] = {0};
    for (size_t c = 0; c < x->n_ch; ++c)
    {
        saved[c] = x->res->chan[c].noise_sd;
        x->res->chan[c].noise_sd = NOMINAL_NOISE * x->res->chan[c].scale;
    }
    aenl_status_t st = sim_sig(x, m, 0u, s0, NULL, NULL, err);
    if (st == AENL_OK && run_bounded(s0, x->n_ch))
    {
        double fl = 0.0;
        st = floor_same(x, m, s0, n_rep, &fl, rv, err);
    }
    for (size_t c = 0; c < x->n_ch; ++c)
    {
        x->res->chan[c].noise_sd = saved[c];
    }
    free(s0);
    return st;
}

/* Replicates 1..n_rep of model m (their own excitation and noise seeds) into the signatures
 * s + r n_ch, at once, each on its own copy of the context. */
typedef struct
{
    const ctx_t *x;
    const aenl_sim_model_t *m;
    aenl_diagnose_sig_t *s;
    unsigned *sims;
} rep_job_t;

static aenl_status_t rep_task(void *ctx, size_t i, aenl_err_t *err)
{
    const rep_job_t *j = (const rep_job_t *)ctx;
    ctx_t x = *j->x;
    x.n_sims = 0;
    const aenl_status_t st =
        sim_sig(&x, j->m, (unsigned)i + 1u, j->s + (i + 1u) * x.n_ch, NULL, NULL, err);
    j->sims[i] = x.n_sims;
    return st;
}

static aenl_status_t replicate_sigs(ctx_t *x, const aenl_sim_model_t *m, unsigned n_rep,
                                    aenl_diagnose_sig_t *s, aenl_err_t *err)
{
    unsigned *sims = calloc(n_rep > 0u ? n_rep : 1u, sizeof(*sims));
    if (sims == NULL)
    {
        aenl_err_set(err, "out of memory (replicates)");
        return AENL_E_DIM;
    }
    rep_job_t job = {x, m, s, sims};
    const aenl_status_t st = aenl_parallel_try(n_rep, rep_task, &job, err);
    for (unsigned r = 0; r < n_rep; ++r)
    {
        x->n_sims += sims[r];
    }
    free(sims);
    return st;
}

static aenl_status_t floor_of(ctx_t *x, const aenl_sim_model_t *m,
                              const aenl_diagnose_sig_t *main_sig, unsigned n_rep, floor_t *fl,
                              double *elem, aenl_err_t *err)
{
    const size_t n_run = (size_t)n_rep + 1u;
    aenl_diagnose_sig_t *s = malloc(n_run * x->n_ch * sizeof(*s));
    if (s == NULL)
    {
        aenl_err_set(err, "out of memory (replicates)");
        return AENL_E_DIM;
    }
    memcpy(s, main_sig, x->n_ch * sizeof(*s));
    aenl_status_t st = replicate_sigs(x, m, n_rep, s, err);
    memset(fl, 0, sizeof(*fl));
    const size_t per_ch = (size_t)N_FAM * AENL_DIAGNOSE_N_CURVE;
    if (elem != NULL)
    {
        memset(elem, 0, x->n_ch * per_ch * sizeof(double));
    }
    size_t n_pair = 0, n_bounded = 0;
    double sum4 = 0.0;
    for (size_t i = 0; i < n_run && st == AENL_OK; ++i)
    {
        n_bounded += run_bounded(s + i * x->n_ch, x->n_ch) ? 1u : 0u;
        for (size_t j = i + 1u; j < n_run; ++j)
        {
            if (!run_bounded(s + i * x->n_ch, x->n_ch) || !run_bounded(s + j * x->n_ch, x->n_ch))
            {
                continue;
            }
            double ch[N_CH_MAX] = {0}, fam[N_CH_MAX][N_FAM] = {{0}};
            const double g = gap_of(x, s + i * x->n_ch, s + j * x->n_ch, ch, fam);
            fl->ch[x->n_ch] += g * g;
            sum4 += g * g * g * g;
            for (size_t c = 0; c < x->n_ch; ++c)
            {
                fl->ch[c] += ch[c] * ch[c];
                for (int f = 0; f < N_FAM; ++f)
                {
                    fl->fam[c][f] += fam[c][f] * fam[c][f];
                    if (elem == NULL)
                    {
                        continue;
                    }
                    const size_t ne =
                        aenl_diagnose_n_elements(&x->res->chan[c], (aenl_diagnose_family_t)f);
                    for (size_t e = 0; e < ne; ++e)
                    {
                        double w = 0.0;
                        const double d = aenl_diagnose_element(
                            &x->res->chan[c], &s[i * x->n_ch + c], &s[j * x->n_ch + c],
                            (aenl_diagnose_family_t)f, e, &w);
                        elem[c * per_ch + (size_t)f * AENL_DIAGNOSE_N_CURVE + e] +=
                            isfinite(d) ? d * d : 0.0;
                    }
                }
            }
            n_pair++;
        }
    }
    free(s);
    if (st != AENL_OK)
    {
        return st;
    }
    fl->bounded = (double)n_bounded / (double)n_run;
    const double np = n_pair > 0u ? (double)n_pair : 1.0; /* no pair: floors 0 */
    fl->same = sqrt(fl->ch[x->n_ch] / np);
    fl->rv = aenl_diagnose_rel_var(fl->ch[x->n_ch], sum4, n_pair, n_run);
    fl->rv_same = fl->rv;
    if (x->run.turbulence && x->run.turb_intensity > 0.0)
    {
        st = floor_same(x, m, main_sig, n_rep, &fl->same, &fl->rv_same, err);
        if (st != AENL_OK)
        {
            return st;
        }
    }
    for (size_t c = 0; c <= x->n_ch; ++c)
    {
        fl->ch[c] = sqrt(fl->ch[c] / np);
    }
    for (size_t c = 0; c < x->n_ch; ++c)
    {
        for (int f = 0; f < N_FAM; ++f)
        {
            fl->fam[c][f] = sqrt(fl->fam[c][f] / np);
        }
    }
    if (elem != NULL)
    {
        for (size_t i = 0; i < x->n_ch * per_ch; ++i)
        {
            elem[i] = sqrt(elem[i] / np);
        }
    }
    return AENL_OK;
}

/* ---- candidates ------------------------------------------------------------------------------ */

typedef struct
{
    double s;                            /* signal std of the DOF's channel (noise removed) */
    double m;                            /* mean of the DOF's channel */
    double p0;                           /* preload: first guess of M0 / s */
    double theta[AENL_DIAGNOSE_MAX_PAR]; /* best so far */
    double best;                         /* best objective (gap^2) */
    aenl_diagnose_effect_t effect;
    aenl_sim_dof_t dof;
    unsigned n_par;
    unsigned n_evals;
} spec_t;

/* Parameters theta (scaled, unconstrained) to the DOF's law; docs/diagnose.md lists the maps. */
static void spec_law(const spec_t *sp, const double *th, aenl_sim_law_t *law)
{
    memset(law, 0, sizeof(*law));
    switch (sp->effect)
    {
        case AENL_DIAGNOSE_FREEPLAY:
        {
            const double delta = sp->s * exp(th[0]);
            law->kind = AENL_SIM_LAW_FREEPLAY;
            law->delta = delta;
            law->x_f = sp->m + sp->s * th[1] - 0.5 * delta;
            break;
        }
        case AENL_DIAGNOSE_HYSTERESIS:
        {
            const double delta = sp->s * exp(th[0]);
            law->kind = AENL_SIM_LAW_HYSTERESIS;
            law->delta = delta;
            law->x_f = delta * th[1];
            law->preload = delta * th[2];
            break;
        }
        case AENL_DIAGNOSE_POLYNOMIAL:
            /* x + c3 x^3, or with a second parameter x + c3 x^3 + c5 x^5 */
            law->kind = AENL_SIM_LAW_POLYNOMIAL;
            law->n_coeffs = sp->n_par > 1u ? 5u : 3u;
            law->coeffs[0] = 1.0;
            law->coeffs[2] = 0.01 * sinh(th[0]) / (sp->s * sp->s);
            if (sp->n_par > 1u)
            {
                law->coeffs[4] = 0.01 * sinh(th[1]) / (sp->s * sp->s * sp->s * sp->s);
            }
            break;
        case AENL_DIAGNOSE_PRELOAD:
            /* M = M0 + x: the Lee freeplay with inner stiffness 1 has no gap at all. */
            law->kind = AENL_SIM_LAW_FREEPLAY;
            law->delta = 1e-9;
            law->x_f = 0.0;
            law->preload = sp->s * th[0];
            law->inner_stiffness = 1.0;
            break;
        case AENL_DIAGNOSE_NONE:
        default:
            law->kind = AENL_SIM_LAW_LINEAR;
            break;
    }
}

typedef struct
{
    ctx_t *x;
    const aenl_sim_model_t *base;
    spec_t *sp;
    aenl_diagnose_sig_t *sig; /* scratch, n_ch */
    aenl_err_t *err;
    aenl_status_t st;
} obj_t;

/* The total gap squared of candidate sp with parameters th into *j (sig: scratch, n_ch). */
static aenl_status_t gap2_of(ctx_t *x, const aenl_sim_model_t *base, const spec_t *sp,
                             const double *th, aenl_diagnose_sig_t *sig, double *j, aenl_err_t *err)
{
    aenl_sim_model_t m = *base;
    spec_law(sp, th, &m.law[sp->dof]);
    const aenl_status_t st = sim_sig(x, &m, 0, sig, NULL, NULL, err);
    const double g = st == AENL_OK ? gap_of(x, x->res->sig_meas, sig, NULL, NULL) : HUGE_VAL;
    *j = g * g;
    return st;
}

/* An evaluation of candidate sp at th that gave j: counted, and kept when it is the best. */
static void note_eval(spec_t *sp, const double *th, double j)
{
    sp->n_evals++;
    if (j < sp->best)
    {
        sp->best = j;
        memcpy(sp->theta, th, sizeof(double) * sp->n_par);
    }
}

/* Objective: total gap squared of the candidate with parameters th. */
static double objective(obj_t *o, const double *th)
{
    if (o->st != AENL_OK)
    {
        return HUGE_VAL;
    }
    double j = HUGE_VAL;
    o->st = gap2_of(o->x, o->base, o->sp, th, o->sig, &j, o->err);
    if (o->st != AENL_OK)
    {
        return HUGE_VAL;
    }
    note_eval(o->sp, th, j);
    return j;
}

/* Coarse grid of first guesses, per effect; returns the count (rows of AENL_DIAGNOSE_MAX_PAR). */
static size_t spec_grid(const spec_t *sp, double g[][AENL_DIAGNOSE_MAX_PAR])
{
    size_t n = 0;
    switch (sp->effect)
    {
        case AENL_DIAGNOSE_FREEPLAY:
        {
            const double d[] = {0.1, 0.25, 0.6, 1.5};
            for (size_t i = 0; i < 4u; ++i)
            {
                g[n][0] = log(d[i]);
                g[n][1] = 0.0;
                n++;
            }
            break;
        }
        case AENL_DIAGNOSE_HYSTERESIS:
        {
            /* alpha_f / delta and M0 / delta: gaps away from the origin, and the paper's loop
             * (alpha_f 0, M0 half way to the closed loop's delta / 2). With every start at
             * alpha_f > 0, a loop with alpha_f 0 under turbulence the model does not share stays
             * far from its best gap, and a cubic is named instead. No start at the centred
             * freeplay the law holds (alpha_f -delta / 2, M0 0; test_sim_lco): from there a loop
             * of 1 to 3 % of a true freeplay's width beats the freeplay. */
            const double d[] = {0.15, 0.4, 1.0};
            const double ab[][2] = {{0.5, 0.5}, {0.25, 1.0}, {1.0, 0.25}, {0.0, 0.25}};
            for (size_t i = 0; i < 3u; ++i)
            {
                for (size_t k = 0; k < 4u; ++k)
                {
                    g[n][0] = log(d[i]);
                    g[n][1] = ab[k][0];
                    g[n][2] = ab[k][1];
                    n++;
                }
            }
            break;
        }
        case AENL_DIAGNOSE_POLYNOMIAL:
            if (sp->n_par > 1u)
            {
                /* Softening that stiffens again: c5 = r c3^2 keeps the stiffness
                 * 1 + 3 c3 x^2 + 5 c5 x^4 above 1 - 0.45 / r > 0 (in units of the std). */
                const double c[] = {-0.05, -0.2, -0.8, -3.0};
                const double r[] = {0.5, 1.0};
                for (size_t i = 0; i < 4u; ++i)
                {
                    for (size_t k = 0; k < 2u; ++k)
                    {
                        g[n][0] = asinh(c[i] / 0.01);
                        g[n][1] = asinh(r[k] * c[i] * c[i] / 0.01);
                        n++;
                    }
                }
            }
            else
            {
                const double c[] = {-0.1, -0.02, 0.01, 0.04, 0.15, 0.6, 2.5};
                for (size_t i = 0; i < 7u; ++i)
                {
                    g[n++][0] = asinh(c[i] / 0.01);
                }
            }
            break;
        case AENL_DIAGNOSE_PRELOAD:
            g[n++][0] = sp->p0;
            g[n++][0] = sp->p0 - 0.5;
            g[n++][0] = sp->p0 + 0.5;
            break;
        case AENL_DIAGNOSE_NONE:
        default:
            break;
    }
    return n;
}

/* Nelder-Mead from sp->theta (standard coefficients 1, 2, 1/2, 1/2). */
static void nelder_mead(obj_t *o, const double *step, unsigned max_evals)
{
    const unsigned np = o->sp->n_par;
    double v[AENL_DIAGNOSE_MAX_PAR + 1][AENL_DIAGNOSE_MAX_PAR] = {{0}};
    double fv[AENL_DIAGNOSE_MAX_PAR + 1] = {0};
    const unsigned start = o->sp->n_evals;
    for (unsigned i = 0; i <= np; ++i)
    {
        memcpy(v[i], o->sp->theta, sizeof(double) * np);
        if (i > 0u)
        {
            v[i][i - 1u] += step[i - 1u];
        }
        fv[i] = (i == 0u) ? o->sp->best : objective(o, v[i]);
    }
    while (o->sp->n_evals - start < max_evals && o->st == AENL_OK)
    {
        /* order: best first */
        for (unsigned i = 1; i <= np; ++i)
        {
            for (unsigned k = i; k > 0u && fv[k] < fv[k - 1u]; --k)
            {
                double t = fv[k];
                fv[k] = fv[k - 1u];
                fv[k - 1u] = t;
                for (unsigned p = 0; p < np; ++p)
                {
                    t = v[k][p];
                    v[k][p] = v[k - 1u][p];
                    v[k - 1u][p] = t;
                }
            }
        }
        if (fabs(fv[np] - fv[0]) <= 1e-4 * fabs(fv[0]) + 1e-12)
        {
            break;
        }
        double cen[AENL_DIAGNOSE_MAX_PAR] = {0};
        for (unsigned i = 0; i < np; ++i)
        {
            for (unsigned p = 0; p < np; ++p)
            {
                cen[p] += v[i][p] / (double)np;
            }
        }
        double xr[AENL_DIAGNOSE_MAX_PAR] = {0}, xc[AENL_DIAGNOSE_MAX_PAR] = {0};
        for (unsigned p = 0; p < np; ++p)
        {
            xr[p] = cen[p] + (cen[p] - v[np][p]);
        }
        const double fr = objective(o, xr);
        if (fr < fv[0])
        {
            double xe[AENL_DIAGNOSE_MAX_PAR] = {0};
            for (unsigned p = 0; p < np; ++p)
            {
                xe[p] = cen[p] + 2.0 * (cen[p] - v[np][p]);
            }
            const double fe = objective(o, xe);
            memcpy(v[np], fe < fr ? xe : xr, sizeof(double) * np);
            fv[np] = fe < fr ? fe : fr;
            continue;
        }
        if (fr < fv[np - 1u])
        {
            memcpy(v[np], xr, sizeof(double) * np);
            fv[np] = fr;
            continue;
        }
        const int outside = fr < fv[np];
        for (unsigned p = 0; p < np; ++p)
        {
            xc[p] = outside ? cen[p] + 0.5 * (xr[p] - cen[p]) : cen[p] + 0.5 * (v[np][p] - cen[p]);
        }
        const double fc = objective(o, xc);
        if (fc < (outside ? fr : fv[np]))
        {
            memcpy(v[np], xc, sizeof(double) * np);
            fv[np] = fc;
            continue;
        }
        for (unsigned i = 1; i <= np; ++i)
        {
            for (unsigned p = 0; p < np; ++p)
            {
                v[i][p] = v[0][p] + 0.5 * (v[i][p] - v[0][p]);
            }
            fv[i] = objective(o, v[i]);
        }
    }
}

static void spec_step(const spec_t *sp, double *step)
{
    switch (sp->effect)
    {
        case AENL_DIAGNOSE_FREEPLAY:
            step[0] = 0.4;
            step[1] = 0.3;
            break;
        case AENL_DIAGNOSE_HYSTERESIS:
            step[0] = 0.4;
            step[1] = 0.25;
            step[2] = 0.25;
            break;
        case AENL_DIAGNOSE_POLYNOMIAL:
            step[0] = 0.7;
            step[1] = 0.7;
            break;
        case AENL_DIAGNOSE_PRELOAD:
        case AENL_DIAGNOSE_NONE:
        default:
            step[0] = 0.2;
            break;
    }
}

/* ---- the record ----------------------------------------------------------------------------- */

static aenl_status_t take_record(const aenl_table_t *t, const aenl_sim_run_t *run,
                                 aenl_diagnose_result_t *r, const char *const *names,
                                 const char *time_column, aenl_err_t *err)
{
    long tc = -1;
    for (size_t c = 0; c < t->n_cols; ++c)
    {
        if (aenl_csv_is_time_column(t->names[c], time_column))
        {
            tc = (long)c;
            break;
        }
    }
    if (tc < 0)
    {
        aenl_err_set(err, "no time column (t, time, tau or timestamp, alone or with a unit; "
                          "another name with --time COL)");
        return AENL_E_ARG;
    }
    if (t->n_rows < 512u)
    {
        aenl_err_set(err, "%zu samples: at least 512 are needed", t->n_rows);
        return AENL_E_ARG;
    }
    for (size_t c = 0; c < r->n_channels; ++c)
    {
        if (aenl_table_find(t, names[c]) < 0)
        {
            aenl_err_set(err, "no column '%s' (the model's output channels are needed by name)",
                         names[c]);
            return AENL_E_ARG;
        }
    }
    const double *tt = aenl_table_col(t, (size_t)tc);
    const size_t n = t->n_rows;
    for (size_t i = 0; i + 1u < n; ++i)
    {
        const double step = tt[i + 1u] - tt[i];
        if (!isfinite(step) || fabs(step - run->dt) > 0.05 * run->dt)
        {
            aenl_err_set(err,
                         "time step %g at data row %zu differs from the model's [run] dt = %g "
                         "(the record must be sampled uniformly at dt, in the model's time unit)",
                         step, i + 2u, run->dt);
            return AENL_E_ARG;
        }
    }
    const double dt_mean = (tt[n - 1u] - tt[0]) / (double)(n - 1u);
    if (fabs(dt_mean - run->dt) > 1e-3 * run->dt)
    {
        aenl_err_set(err, "mean time step %.9g differs from the model's [run] dt = %.9g", dt_mean,
                     run->dt);
        return AENL_E_ARG;
    }
    r->n_samples = n;
    r->dt = run->dt;
    r->y_meas = malloc(r->n_channels * n * sizeof(double));
    if (r->y_meas == NULL)
    {
        aenl_err_set(err, "out of memory (record)");
        return AENL_E_DIM;
    }
    for (size_t c = 0; c < r->n_channels; ++c)
    {
        const long col = aenl_table_find(t, names[c]);
        memcpy(r->y_meas + c * n, aenl_table_col(t, (size_t)col), n * sizeof(double));
        r->names[c] = names[c];
        aenl_err_t e;
        aenl_err_clear(&e);
        const aenl_status_t st = aenl_diagnose_chan_setup(r->y_meas + c * n, n, &r->chan[c], &e);
        if (st != AENL_OK)
        {
            aenl_err_set(err, "channel %s: %s", names[c], e.msg);
            return st;
        }
    }
    return AENL_OK;
}

/* ---- disagreements ----------------------------------------------------------------------------
 */

static void add_disagreements(aenl_diagnose_result_t *r, const double *elem, double ratio)
{
    const size_t per_ch = (size_t)N_FAM * AENL_DIAGNOSE_N_CURVE;
    r->n_dis = 0;
    for (size_t c = 0; c < r->n_channels; ++c)
    {
        const aenl_diagnose_chan_t *ch = &r->chan[c];
        for (int f = 0; f < N_FAM; ++f)
        {
            const double sig = r->sig_before[c][f];
            if (!(sig > ratio))
            {
                continue;
            }
            double lo = HUGE_VAL, hi = -HUGE_VAL;
            const size_t ne = aenl_diagnose_n_elements(ch, (aenl_diagnose_family_t)f);
            const aenl_diagnose_sig_t *a = &r->sig_meas[c], *b = &r->sig_base[c];
            for (size_t e = 0; e < ne; ++e)
            {
                double w = 0.0;
                const double d = aenl_diagnose_element(ch, a, b, (aenl_diagnose_family_t)f, e, &w);
                const double fe = elem[c * per_ch + (size_t)f * AENL_DIAGNOSE_N_CURVE + e];
                if (!(w > 0.0) || !isfinite(d) || !(fabs(d) > 2.0 * fe + 1e-12))
                {
                    continue;
                }
                double p0 = 0.0, p1 = 0.0;
                if (f == AENL_DIAGNOSE_AMPLITUDE && e < AENL_DIAGNOSE_N_QUANT)
                {
                    p0 = a->quant[e];
                    p1 = b->valid ? b->quant[e] : a->quant[e];
                }
                else if (f == AENL_DIAGNOSE_AMPLITUDE)
                {
                    const size_t k = e - AENL_DIAGNOSE_N_QUANT;
                    const double env = fmax(a->env[k], b->valid ? b->env[k] : 0.0);
                    p0 = ch->mean - env;
                    p1 = ch->mean + env;
                }
                else if (f == AENL_DIAGNOSE_SPECTRUM)
                {
                    p0 = (double)ch->band_lo[e] / ((double)ch->seg * r->dt);
                    p1 = (double)ch->band_hi[e] / ((double)ch->seg * r->dt);
                }
                else
                {
                    const size_t node = e % AENL_DIAGNOSE_N_GRID;
                    p0 = ch->x_min + (ch->x_max - ch->x_min) * (double)node /
                                         (double)(AENL_DIAGNOSE_N_GRID - 1u);
                    p1 = p0;
                }
                lo = fmin(lo, fmin(p0, p1));
                hi = fmax(hi, fmax(p0, p1));
            }
            if (!(hi >= lo))
            {
                lo = ch->x_min;
                hi = ch->x_max;
            }
            aenl_diagnose_dis_t *dd = &r->dis[r->n_dis++];
            dd->channel = c;
            dd->family = (aenl_diagnose_family_t)f;
            dd->lo = lo;
            dd->hi = hi;
            dd->significance = sig;
        }
    }
    /* most significant first */
    for (size_t i = 1; i < r->n_dis; ++i)
    {
        for (size_t k = i; k > 0u && r->dis[k].significance > r->dis[k - 1u].significance; --k)
        {
            const aenl_diagnose_dis_t t = r->dis[k];
            r->dis[k] = r->dis[k - 1u];
            r->dis[k - 1u] = t;
        }
    }
}

/* ---- main ----------------------------------------------------------------------------------- */

void aenl_diagnose_result_free(aenl_diagnose_result_t *r)
{
    if (r == NULL)
    {
        return;
    }
    free(r->psd_meas);
    free(r->psd_base);
    free(r->psd_upd);
    free(r->y_meas);
    free(r->y_base);
    free(r->y_upd);
    memset(r, 0, sizeof(*r));
}

static void set_sig(aenl_diagnose_result_t *r, const floor_t *fl, double fam[][N_FAM],
                    double sig[][N_FAM])
{
    for (size_t c = 0; c < r->n_channels; ++c)
    {
        for (int f = 0; f < N_FAM; ++f)
        {
            /* A family without comparable elements between replicates (the model never reaches the
             * record's amplitudes) has no floor of its own: the channel's stands in. */
            const double fl_f = fl->fam[c][f] > 0.0 ? fl->fam[c][f] : fl->ch[c];
            sig[c][f] = fam[c][f] / fmax(fl_f, AENL_DIAGNOSE_MIN_FLOOR);
        }
    }
}

/* One more stage of the search done, reported to the options' progress receiver. */
static void advance(ctx_t *x)
{
    x->step++;
    aenl_progress_report(x->progress, x->step < x->steps ? x->step : x->steps, x->steps);
}

static void progress(const ctx_t *x, const char *fmt, const char *a, const char *b, double g)
{
    if (x->verbose)
    {
        fprintf(stderr, "diagnose: ");
        fprintf(stderr, fmt, a, b, g);
        fprintf(stderr, " (%u simulations)\n", x->n_sims);
    }
}

/* Signal std of a DOF's channel: the measured std with the noise removed. */
static double signal_std(const aenl_diagnose_chan_t *c)
{
    const double v = c->scale * c->scale - c->noise_sd * c->noise_sd;
    return sqrt(fmax(v, 0.01 * c->scale * c->scale));
}

/* order[0..n) = the candidates by ascending best gap (insertion sort: n is a handful). */
static void order_by_best(const spec_t *sp, size_t n, size_t *order)
{
    for (size_t k = 0; k < n; ++k)
    {
        order[k] = k;
    }
    for (size_t i = 1; i < n; ++i)
    {
        for (size_t k = i; k > 0u && sp[order[k]].best < sp[order[k - 1u]].best; --k)
        {
            const size_t t = order[k];
            order[k] = order[k - 1u];
            order[k - 1u] = t;
        }
    }
}

/* One evaluation of the coarse grid: candidate k at th, on its own copy of the context (the
 * simulations it counts are added afterwards, in order). */
typedef struct
{
    size_t k;
    double th[AENL_DIAGNOSE_MAX_PAR];
    double j;
    unsigned sims;
} grid_task_t;

typedef struct
{
    ctx_t *x;
    const aenl_sim_model_t *base;
    const spec_t *sp;
    grid_task_t *task;
} grid_job_t;

static aenl_status_t grid_task(void *ctx, size_t i, aenl_err_t *err)
{
    const grid_job_t *g = (const grid_job_t *)ctx;
    grid_task_t *t = &g->task[i];
    ctx_t x = *g->x;
    x.n_sims = 0;
    aenl_diagnose_sig_t *sig = malloc(x.n_ch * sizeof(*sig));
    if (sig == NULL)
    {
        aenl_err_set(err, "out of memory (signatures)");
        return AENL_E_DIM;
    }
    const aenl_status_t st = gap2_of(&x, g->base, &g->sp[t->k], t->th, sig, &t->j, err);
    t->sims = x.n_sims;
    free(sig);
    return st;
}

/* Stage 1: the coarse grid of every candidate, all its points at once. */
static aenl_status_t run_grid(ctx_t *x, const aenl_sim_model_t *base, spec_t *sp, size_t n_sp,
                              aenl_err_t *err)
{
    double g[AENL_DIAGNOSE_MAX_CAND][16][AENL_DIAGNOSE_MAX_PAR];
    size_t ng[AENL_DIAGNOSE_MAX_CAND];
    size_t n_task = 0;
    for (size_t k = 0; k < n_sp; ++k)
    {
        memset(g[k], 0, sizeof(g[k]));
        ng[k] = spec_grid(&sp[k], g[k]);
        n_task += ng[k];
    }
    grid_task_t *task = calloc(n_task > 0u ? n_task : 1u, sizeof(*task));
    if (task == NULL)
    {
        aenl_err_set(err, "out of memory (grid)");
        return AENL_E_DIM;
    }
    for (size_t k = 0, i = 0; k < n_sp; ++k)
    {
        for (size_t q = 0; q < ng[k]; ++q, ++i)
        {
            task[i].k = k;
            memcpy(task[i].th, g[k][q], sizeof(g[k][q]));
        }
    }
    grid_job_t job = {x, base, sp, task};
    const aenl_status_t st = aenl_parallel_try(n_task, grid_task, &job, err);
    for (size_t k = 0, i = 0; k < n_sp && st == AENL_OK; ++k)
    {
        sp[k].best = HUGE_VAL;
        memcpy(sp[k].theta, g[k][0], sizeof(g[k][0]));
        for (size_t q = 0; q < ng[k]; ++q, ++i)
        {
            x->n_sims += task[i].sims;
            note_eval(&sp[k], task[i].th, task[i].j);
        }
        progress(x, "grid %s %s: gap %.4g", aenl_diagnose_effect_name(sp[k].effect),
                 aenl_diagnose_dof_name(sp[k].dof), sqrt(sp[k].best));
        advance(x);
    }
    free(task);
    return st;
}

/* Nelder-Mead on several candidates at once (stages 2 and 3): candidate sp[order[i]] for
 * i < n, each on its own copy of the context; progress is reported afterwards, in order. */
typedef struct
{
    ctx_t *x;
    const aenl_sim_model_t *base;
    spec_t *sp;
    const size_t *order;
    unsigned max_evals;
    unsigned *sims;
} refine_job_t;

static aenl_status_t refine_task(void *ctx, size_t i, aenl_err_t *err)
{
    const refine_job_t *r = (const refine_job_t *)ctx;
    ctx_t x = *r->x;
    x.n_sims = 0;
    aenl_diagnose_sig_t *sig = malloc(x.n_ch * sizeof(*sig));
    if (sig == NULL)
    {
        aenl_err_set(err, "out of memory (signatures)");
        return AENL_E_DIM;
    }
    spec_t *s = &r->sp[r->order[i]];
    obj_t o = {&x, r->base, s, sig, err, AENL_OK};
    double step[AENL_DIAGNOSE_MAX_PAR] = {0.0};
    spec_step(s, step);
    nelder_mead(&o, step, r->max_evals);
    r->sims[i] = x.n_sims;
    free(sig);
    return o.st;
}

static aenl_status_t refine_all(ctx_t *x, const aenl_sim_model_t *base, spec_t *sp,
                                const size_t *order, size_t n, unsigned max_evals, const char *fmt,
                                aenl_err_t *err)
{
    unsigned sims[AENL_DIAGNOSE_MAX_CAND] = {0};
    refine_job_t job = {x, base, sp, order, max_evals, sims};
    const aenl_status_t st = aenl_parallel_try(n, refine_task, &job, err);
    for (size_t i = 0; i < n && st == AENL_OK; ++i)
    {
        x->n_sims += sims[i];
        const spec_t *s = &sp[order[i]];
        progress(x, fmt, aenl_diagnose_effect_name(s->effect), aenl_diagnose_dof_name(s->dof),
                 sqrt(s->best));
        advance(x);
    }
    return st;
}

static aenl_status_t run_candidates(ctx_t *x, const aenl_sim_model_t *base, spec_t *sp, size_t n_sp,
                                    const aenl_diagnose_opts_t *opts, aenl_err_t *err)
{
    aenl_status_t st = run_grid(x, base, sp, n_sp, err);
    if (st != AENL_OK)
    {
        return st;
    }
    /* Stage 2: Nelder-Mead from the best grid point of the most promising candidates. */
    size_t order[AENL_DIAGNOSE_MAX_CAND];
    order_by_best(sp, n_sp, order);
    const size_t n = n_sp < opts->n_refine ? n_sp : opts->n_refine;
    return refine_all(x, base, sp, order, n, opts->max_evals, "refined %s %s: gap %.4g", err);
}

/* Upper 0.1 % point of chi-square with k degrees of freedom (Wilson-Hilferty; within 1 % for
 * k >= 5). */
static double chi2_quantile_999(double k)
{
    const double z = 3.090232306167814; /* standard normal 99.9 % point */
    const double a = 2.0 / (9.0 * k);
    const double c = 1.0 - a + z * sqrt(a);
    return k * c * c * c;
}

/* Rivals of the best score refitted to the summaries (summaries_choose). */
#define N_RIVALS 3

/* One candidate's summary fit (stage 4: aenl_diagnose_fit_summaries from its gap-fitted law, a
 * quarter of the records for the sensitivities); st the fit's own status (a fit that cannot
 * run: an unusable record). */
typedef struct sumfit
{
    aenl_diagnose_sumfit_t f;
    aenl_status_t st;
    int rejected; /* chi2 beyond its 99.9 % point */
} sumfit_t;

/* The weighting is efficient only for a model that can match the summaries. If even the fitted
 * one misses them beyond chance (the test of over-identifying restrictions at 0.1 %), the most
 * precise summaries are the most misleading: the model is rejected and the gap's fit kept. */
static aenl_status_t sumfit_of(ctx_t *x, const aenl_diagnose_opts_t *opts,
                               const aenl_sim_model_t *base, const aenl_diagnose_cand_t *cd,
                               sumfit_t *out, aenl_err_t *err)
{
    memset(out, 0, sizeof(*out));
    const aenl_diagnose_result_t *r = x->res;
    double noise[N_CH_MAX];
    for (size_t c = 0; c < x->n_ch; ++c)
    {
        noise[c] = r->chan[c].noise_sd;
    }
    aenl_sim_model_t with_law = *base, m;
    with_law.law[cd->dof] = cd->law;
    if (own_start(x, &with_law, &m, NULL, err) != AENL_OK)
    {
        return AENL_E_DIM;
    }
    aenl_err_t e;
    aenl_err_clear(&e);
    const aenl_sim_run_t run = bounded_run(x);
    out->st =
        aenl_diagnose_fit_summaries(&m, &run, cd->effect, cd->dof, noise, r->y_meas, x->n,
                                    opts->summary_records, opts->summary_records / 4u, &out->f, &e);
    if (out->st == AENL_E_DIM)
    {
        aenl_err_set(err, "%s", e.msg);
        return out->st;
    }
    x->n_sims += out->f.n_sims;
    out->rejected = out->st == AENL_OK && out->f.chi2 > chi2_quantile_999((double)out->f.dof);
    progress(x, "summary fit of %s %s: chi2 %.4g", aenl_diagnose_effect_name(cd->effect),
             aenl_diagnose_dof_name(cd->dof), out->st == AENL_OK ? out->f.chi2 : (double)NAN);
    return AENL_OK;
}

/* Stage 4 (opts->summary_records > 0): the named effect's parameters refitted to the record's
 * summaries (amplitude, frequency, kurtosis, harmonics of every channel) with their efficient
 * weighting, and their standard errors. The gap weighs its many curve and spectrum elements by
 * fixed scales, so a clear misfit of one precise summary can hide in their spread: on the
 * docs/diagnose.md's worked example (3-DOF flap freeplay, an irregular limit cycle) the gap's
 * estimate of the gap width was 16 % short and its flap amplitude 18 % (40 standard deviations) too
 * small; refitted, the width is 0.1 % off. A fit that cannot run keeps the gap's estimate and
 * reports the errors as not determined; a rejected one keeps it without errors. */
static void apply_sumfit(aenl_diagnose_result_t *r, const sumfit_t *s, int *moved)
{
    *moved = 0;
    r->n_param_sd = s->f.n_par;
    for (size_t k = 0; k < s->f.n_par; ++k)
    {
        r->param_sd[k] = s->st == AENL_OK ? s->f.sd[k] : (double)INFINITY;
    }
    if (s->st == AENL_OK)
    {
        r->chi2_start = s->f.chi2_start;
        r->chi2 = s->f.chi2;
        r->chi2_dof = s->f.dof;
        r->summary_rejected = s->rejected;
        if (r->summary_rejected)
        {
            r->n_param_sd = 0;
        }
        else
        {
            r->updated.law[r->dof] = s->f.law;
            *moved = 1;
        }
    }
}

/* The laws the gap's scores do not tell from the best: for each other effect or DOF, its
 * least-score candidate within one parameter's penalty of the best score that also takes 30 %
 * off the baseline's gap (it could be named in the best's place); at most N_RIVALS, least
 * score first, into v. Their count. */
static size_t rivals_of(const aenl_diagnose_result_t *r, size_t best, double penalty,
                        size_t v[N_RIVALS])
{
    const aenl_diagnose_cand_t *b = &r->cand[best];
    size_t n_v = 0;
    for (size_t i = 0; i < r->n_cand; ++i)
    {
        const aenl_diagnose_cand_t *cd = &r->cand[i];
        int ok = (cd->effect != b->effect || cd->dof != b->dof) && cd->score - b->score < penalty &&
                 cd->gap < 0.7 * r->gap_before[r->n_channels];
        for (size_t j = 0; j < r->n_cand && ok; ++j)
        {
            const aenl_diagnose_cand_t *o = &r->cand[j];
            ok = !(j != i && o->effect == cd->effect && o->dof == cd->dof &&
                   (o->score < cd->score || (!(o->score > cd->score) && j < i)));
        }
        if (!ok)
        {
            continue;
        }
        /* insert by score; the worst falls off when full */
        size_t k = n_v < N_RIVALS ? n_v++ : N_RIVALS;
        while (k > 0u && r->cand[v[k - 1u]].score > cd->score)
        {
            if (k < N_RIVALS)
            {
                v[k] = v[k - 1u];
            }
            --k;
        }
        if (k < N_RIVALS)
        {
            v[k] = i;
        }
    }
    return n_v;
}

/* Within one parameter's penalty the gap's scores do not tell laws apart (Akaike's rule of
 * thumb: within 2 of the least, both are supported), and under turbulence a freeplay and a
 * hysteresis, or a freeplay and a polynomial, are often that close (docs/diagnose.md). The
 * summaries are few and precise: each such law refitted to them, the one with the least chi2 +
 * penalty x parameters is named, the moment-selection criterion of the method of moments (Andrews &
 * Lu 2001: J less a penalty per over-identifying restriction, each model's J with its own efficient
 * weighting; over the same summaries, the same as J plus a penalty per parameter). A rejected fit,
 * or one that cannot run, takes no part; when the best's own fit cannot run, or every fit is
 * rejected, the gap's choice stands. Only where the gap accepts the best law (gap_accepts):
 * efficient weights are right only for a model that can match the record, and where even the best
 * law misses it beyond chance, every rival does too, and their chi2 compare two misfits, not two
 * laws: with the noise estimated 0 against a baseline far from the record, a true freeplay's
 * summaries can be rejected while a thin loop's are just not, and the loop would be named. sf[k] is
 * the fit of cand con[k], con[0] the best. The index into con of the law named. */
static size_t summaries_choose(const aenl_diagnose_result_t *r, const size_t *con,
                               const sumfit_t *sf, size_t n_con, double penalty)
{
    size_t pick = 0;
    double crit = HUGE_VAL;
    for (size_t k = 0; k < n_con && sf[0].st == AENL_OK; ++k)
    {
        const double c = sf[k].f.chi2 + penalty * r->cand[con[k]].n_params;
        if (sf[k].st == AENL_OK && !sf[k].rejected && c < crit)
        {
            pick = k;
            crit = c;
        }
    }
    return pick;
}

/* The report's rival (r->rival): the runner-up on the summaries among the n_con laws con[],
 * k_pick the named one. */
static void set_rival(aenl_diagnose_result_t *r, const size_t *con, const sumfit_t *sf,
                      size_t n_con, size_t k_pick, double penalty)
{
    double crit = HUGE_VAL;
    for (size_t k = 0; k < n_con; ++k)
    {
        const double c =
            sf[k].st == AENL_OK ? sf[k].f.chi2 + penalty * r->cand[con[k]].n_params : HUGE_VAL;
        if (k != k_pick && (r->rival == r->n_cand || c < crit))
        {
            r->rival = con[k];
            crit = c;
            r->rival_chi2 = sf[k].st == AENL_OK ? sf[k].f.chi2 : (double)NAN;
            r->rival_chi2_dof = sf[k].st == AENL_OK ? sf[k].f.dof : 0u;
            r->rival_rejected = sf[k].rejected;
        }
    }
}

/* Name cand[best], or the rival the summaries prefer where the gap accepts the best law
 * (summaries_choose), and refit the named law to the summaries (stage 4). *moved: 1 when the
 * summary fit moved the named law from the one whose floor was measured. */
static aenl_status_t name_law(ctx_t *x, const aenl_sim_model_t *base,
                              const aenl_diagnose_opts_t *opts, size_t best, int *moved,
                              aenl_err_t *err)
{
    aenl_diagnose_result_t *r = x->res;
    size_t con[1 + N_RIVALS] = {best}; /* the best, then its rivals */
    sumfit_t sf[1 + N_RIVALS];
    memset(sf, 0, sizeof(sf));
    size_t k_pick = 0;
    if (opts->summary_records > 0u)
    {
        const size_t n_con =
            1u + (r->gap_accepts ? rivals_of(r, best, opts->penalty, con + 1) : 0u);
        for (size_t k = 0; k < n_con; ++k)
        {
            const aenl_status_t st = sumfit_of(x, opts, base, &r->cand[con[k]], &sf[k], err);
            if (st != AENL_OK)
            {
                return st;
            }
        }
        k_pick = summaries_choose(r, con, sf, n_con, opts->penalty);
        r->by_summaries = k_pick != 0u;
        set_rival(r, con, sf, n_con, k_pick, opts->penalty);
    }
    const size_t pick = con[k_pick];
    r->chosen = pick;
    r->effect = r->cand[pick].effect;
    r->dof = r->cand[pick].dof;
    r->updated.law[r->dof] = r->cand[pick].law; /* its gap: gap_after */
    if (opts->summary_records > 0u)
    {
        apply_sumfit(r, &sf[k_pick], moved);
        r->cand[pick].law = r->updated.law[r->dof];
    }
    return AENL_OK;
}

/* When the baseline agrees within the noise by the gap: its summaries' test (the record's
 * distance from summary_records records of the baseline in mean, std, kurtosis, peak frequency
 * and harmonics of every channel, ranked among theirs). The gap weighs its many curve and spectrum
 * elements by fixed scales; the summaries are few and precise, so this is a second look with more
 * power on what they measure. A test that cannot run (an unusable record) is left out
 * (base_test.n_rep 0). */
static aenl_status_t test_baseline(ctx_t *x, const aenl_sim_model_t *base,
                                   const aenl_diagnose_opts_t *opts, aenl_diagnose_result_t *r,
                                   aenl_err_t *err)
{
    if (!(r->base_floor > 0.0))
    {
        /* Every replicate alike: a deterministic model (no turbulence, or the record's own)
         * simulated without noise (a noise-free record), whose one run reproduces the record
         * within the least floor. Nothing random is left for the summaries to rank. */
        r->base_exact = 1;
        return AENL_OK;
    }
    double noise[N_CH_MAX];
    for (size_t c = 0; c < x->n_ch; ++c)
    {
        noise[c] = r->chan[c].noise_sd;
    }
    aenl_err_t e;
    aenl_err_clear(&e);
    const aenl_sim_run_t run = bounded_run(x);
    const aenl_status_t st = aenl_diagnose_summary_test(base, &run, noise, r->y_meas, x->n,
                                                        opts->summary_records, &r->base_test, &e);
    if (st == AENL_E_DIM)
    {
        aenl_err_set(err, "%s", e.msg);
        return st;
    }
    x->n_sims += opts->summary_records;
    if (x->verbose && st == AENL_OK)
    {
        fprintf(stderr,
                "diagnose: summary test of the baseline: the record's distance^2 %.4g over %zu "
                "summaries, p %.3g of %u + 1 records\n",
                r->base_test.d2, r->base_test.d, r->base_test.p, r->base_test.n_rep);
    }
    return AENL_OK;
}

/* Mean square of the third differences of y[0..n): 20 sigma^2 for white noise of std sigma, and
 * additive (in expectation) over a response and noise independent of it. */
static double d3_mean_square(const double *y, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i + 3u < n; ++i)
    {
        const double d = y[i + 3u] - 3.0 * y[i + 2u] + 3.0 * y[i + 1u] - y[i];
        s += d * d;
    }
    return s / (double)(n - 3u);
}

/* The measurement noise the simulations get. The record's high-frequency scale (third
 * differences, noise_record) is its noise only where the response is smooth from sample to
 * sample; sampled a few times a period it holds the response's own share, and simulations given
 * all of it as noise carry that share twice: on a noise-free gust record with the pitch sampled 6
 * times a period, the true model's gap is several times its floor, nearly all of it in the pitch
 * spectrum above the resonance. The third differences' mean square adds over response
 * and noise (a robust scale does not: a sampled sinusoid's is bimodal), so the record's beyond
 * the baseline's clean response, over 20, is a second estimate of the noise variance. Each is
 * high for its own reason: the robust scale by the response's sample-to-sample change, the
 * excess by high-frequency content the record has and the baseline lacks (the impacts of a
 * freeplay the baseline does not have: on the noise-free two-freeplay example it is 4 times the
 * robust scale in flap). So the smaller is kept. A baseline that cannot be simulated keeps the
 * record's scale. */
static aenl_status_t baseline_noise(ctx_t *x, const aenl_sim_model_t *base, aenl_err_t *err)
{
    const aenl_sim_run_t run = bounded_run(x);
    aenl_sim_result_t r;
    aenl_err_t e;
    aenl_err_clear(&e);
    x->n_sims++;
    const aenl_status_t st = aenl_sim_simulate(base, &run, &r, &e);
    if (st == AENL_E_DIM)
    {
        aenl_err_set(err, "%s", e.msg);
        return st;
    }
    for (size_t c = 0; c < x->n_ch && st == AENL_OK && r.n_samples >= x->n; ++c)
    {
        const double clean = d3_mean_square(r.y + c * r.n_samples, x->n);
        const double meas = d3_mean_square(x->res->y_meas + c * x->n, x->n);
        if (isfinite(clean))
        {
            x->res->chan[c].noise_sd =
                fmin(x->res->chan[c].noise_record, sqrt(fmax(meas - clean, 0.0) / 20.0));
        }
    }
    aenl_sim_result_free(&r);
    return AENL_OK;
}

/* What one diagnosis carries from stage to stage (diagnose). */
typedef struct
{
    ctx_t x;
    const aenl_sim_model_t *base;
    aenl_sim_model_t
        base_fitted; /* the baseline from its fitted initial state (base points here) */
    const aenl_diagnose_opts_t *opts;
    spec_t sp[AENL_DIAGNOSE_MAX_CAND]; /* the candidates */
    size_t n_sp;
    size_t order[AENL_DIAGNOSE_MAX_CAND]; /* the candidates by ascending best gap */
    floor_t fl_base;                      /* the baseline's floor */
    floor_t fl_cand[N_FLOOR_CAND]; /* the contenders' floors, kept for the named one's after */
    double common, common_same;    /* the common floors: other excitation, the noise alone */
    double rv[2];                  /* the pooled relative variances (pool_rv) and their count */
    size_t n_rv[2];
} diag_t;

/* The candidates run over the record's length, so a sweep or multisine rebuilt from the INI
 * would not be the force the record was driven by. */
static aenl_status_t check_unforced(const aenl_sim_run_t *run, aenl_err_t *err)
{
    if (run->force == AENL_SIM_FORCE_NONE)
    {
        return AENL_OK;
    }
    aenl_err_set(err,
                 "the baseline's [excitation] is a %s: the model-based test does not "
                 "take a forced excitation (it would rebuild the force over the "
                 "record's length instead of using the measured one)",
                 run->force == AENL_SIM_FORCE_SWEEP ? "sweep" : "multisine");
    return AENL_E_ARG;
}

/* Take the record and set up the simulations under its conditions (d->x): its length, no
 * noise of the simulator's own, the runaway bounds, the baseline's noise (baseline_noise). */
static aenl_status_t setup_ctx(diag_t *d, const aenl_table_t *measured, const aenl_sim_run_t *run,
                               const char *const *names, aenl_diagnose_result_t *r, aenl_err_t *err)
{
    aenl_status_t st = take_record(measured, run, r, names, d->opts->time_column, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const size_t n = r->n_samples;
    ctx_t *x = &d->x;
    x->run = *run;
    x->run.duration = (double)(n - 1u) * run->dt;
    x->run.snr = 0.0;
    x->n = n;
    x->n_ch = r->n_channels;
    x->res = r;
    x->noise_seed = d->opts->noise_seed;
    x->verbose = d->opts->verbose;
    x->progress = d->opts->progress;
    for (size_t c = 0; c < x->n_ch; ++c)
    {
        const aenl_diagnose_chan_t *ch = &r->chan[c];
        const double *y = r->y_meas + c * n;
        double reach = 0.0;
        for (size_t i = 0; i < n; ++i)
        {
            reach = fmax(reach, fabs(y[i] - ch->mean));
        }
        x->reach[c] = reach;
        x->bound[c] = fabs(ch->mean) +
                      fmax(RUNAWAY_LIMIT * fmax(ch->scale, fabs(ch->mean)), RUNAWAY_REACH * reach);
    }
    aenl_err_t e;
    aenl_err_clear(&e);
    if (aenl_sim_validate(d->base, &x->run, &e) != AENL_OK)
    {
        aenl_err_set(err, "baseline model: %s", e.msg);
        return AENL_E_ARG;
    }
    if (d->base->initial == AENL_SIM_INITIAL_ESTIMATE && x->run.turbulence)
    {
        aenl_err_set(err, "baseline model: [initial] estimate = true asks for a free decay's "
                          "release, and a record driven by turbulence has none to fit");
        return AENL_E_ARG;
    }
    if (aenl_diagnose_initial_wanted(d->base, &x->run))
    {
        const aenl_sim_run_t wrun = bounded_run(x);
        aenl_err_t fe;
        aenl_err_clear(&fe);
        st = aenl_diagnose_initial_fit(d->base, &wrun, r->y_meas, n, r->chan, &d->base_fitted,
                                       &r->initial, &fe);
        if (st == AENL_E_DIM)
        {
            aenl_err_set(err, "%s", fe.msg);
            return st;
        }
        /* every model from now on is fitted from the baseline's start (own_start); a baseline
         * that runs away within the window cannot be fitted (above its flutter speed, a
         * softening law) and starts from the record's first sample at rest, which r->initial
         * says (window 0) */
        d->base_fitted.initial = AENL_SIM_INITIAL_ESTIMATE;
        d->base = &d->base_fitted;
        x->fit_initial = 1;
    }
    st = baseline_noise(x, d->base, err);
    if (st != AENL_OK)
    {
        return st;
    }
    r->run = x->run;
    return AENL_OK;
}

/* The result's PSD and time-series buffers for its n_ch channels (the PSD arrays strided by the
 * largest Welch segment) and the per-element floor scratch *elem (the caller frees it). */
static aenl_status_t alloc_buffers(aenl_diagnose_result_t *r, size_t n_ch, double **elem,
                                   aenl_err_t *err)
{
    const size_t n = r->n_samples;
    size_t seg_max = 0;
    for (size_t c = 0; c < n_ch; ++c)
    {
        seg_max = r->chan[c].seg > seg_max ? r->chan[c].seg : seg_max;
    }
    r->n_bins = seg_max / 2u + 1u;
    r->psd_meas = calloc(n_ch * r->n_bins, sizeof(double));
    r->psd_base = calloc(n_ch * r->n_bins, sizeof(double));
    r->psd_upd = calloc(n_ch * r->n_bins, sizeof(double));
    r->y_base = malloc(n_ch * n * sizeof(double));
    r->y_upd = malloc(n_ch * n * sizeof(double));
    *elem = malloc(n_ch * (size_t)N_FAM * AENL_DIAGNOSE_N_CURVE * sizeof(double));
    if (!r->psd_meas || !r->psd_base || !r->psd_upd || !r->y_base || !r->y_upd || !*elem)
    {
        free(*elem);
        *elem = NULL;
        aenl_err_set(err, "out of memory (diagnosis buffers)");
        return AENL_E_DIM;
    }
    return AENL_OK;
}

/* The measured signatures of the n_ch channels named `names`; an error for a channel whose
 * record is not finite. */
static aenl_status_t measured_sigs(aenl_diagnose_result_t *r, const char *const *names, size_t n_ch,
                                   aenl_err_t *err)
{
    const size_t n = r->n_samples;
    aenl_status_t st = AENL_OK;
    for (size_t c = 0; c < n_ch && st == AENL_OK; ++c)
    {
        st = aenl_diagnose_signature(r->y_meas + c * n, n, &r->chan[c], &r->sig_meas[c],
                                     r->psd_meas + c * r->n_bins, err);
        if (st == AENL_OK && !r->sig_meas[c].valid)
        {
            aenl_err_set(err, "channel %s: the record is not finite", names[c]);
            st = AENL_E_ARG;
        }
    }
    return st;
}

/* The measured signatures and the baseline's: its gap, its floor and the significant
 * disagreements, over the n_ch channels named `names`. */
static aenl_status_t measure_baseline(diag_t *d, const char *const *names, size_t n_ch,
                                      aenl_err_t *err)
{
    ctx_t *x = &d->x;
    aenl_diagnose_result_t *r = x->res;
    double *elem = NULL;
    aenl_status_t st = alloc_buffers(r, n_ch, &elem, err);
    if (st != AENL_OK)
    {
        return st;
    }
    st = measured_sigs(r, names, n_ch, err);
    if (st == AENL_OK)
    {
        st = sim_sig(x, d->base, 0, r->sig_base, r->y_base, r->psd_base, err);
    }
    if (st == AENL_OK)
    {
        r->gap_before[n_ch] = gap_of(x, r->sig_meas, r->sig_base, r->gap_before, r->fam_before);
        st = floor_of(x, d->base, r->sig_base, d->opts->n_replicates, &d->fl_base, elem, err);
    }
    if (st != AENL_OK)
    {
        free(elem);
        return st;
    }
    memcpy(r->floor_before, d->fl_base.ch, sizeof(r->floor_before));
    set_sig(r, &d->fl_base, r->fam_before, r->sig_before);
    add_disagreements(r, elem, d->opts->report_ratio);
    free(elem);
    progress(x, "baseline %s%s gap %.4g", "", "", r->gap_before[n_ch]);
    return AENL_OK;
}

/* The amplitude the candidates' parameters are scaled by (a gap width, a cubic's strength),
 * channel c: the response's std beyond the noise. But a free decay's std is mostly its quiet
 * tail, while a law acts most where the motion is largest: where the record reaches further
 * than a stationary Gaussian record of its length would (STATIONARY_LEVEL), the scale grows by
 * the excess. A softening cubic scaled by the std of a decay released 28 stds out has lost
 * all its stiffness at the release and runs away. */
static double motion_scale(const ctx_t *x, size_t c)
{
    const aenl_diagnose_chan_t *ch = &x->res->chan[c];
    const double t = sqrt(2.0 * log(2.0 * (double)x->n / STATIONARY_LEVEL));
    return signal_std(ch) * fmax(1.0, x->reach[c] / (t * ch->scale));
}

/* The candidates: every effect on every DOF whose baseline law is linear. */
static void make_specs(diag_t *d)
{
    const aenl_sim_model_t *base = d->base;
    const aenl_diagnose_result_t *r = d->x.res;
    const size_t n_dof = base->type == AENL_SIM_AIRFOIL2DOF ? 2u : 3u;
    const aenl_diagnose_effect_t effects[] = {AENL_DIAGNOSE_FREEPLAY, AENL_DIAGNOSE_HYSTERESIS,
                                              AENL_DIAGNOSE_POLYNOMIAL, AENL_DIAGNOSE_POLYNOMIAL,
                                              AENL_DIAGNOSE_PRELOAD};
    const unsigned n_par[] = {2, 3, 1, 2, 1};
    d->n_sp = 0;
    for (size_t dof = 0; dof < n_dof; ++dof)
    {
        if (base->law[dof].kind != AENL_SIM_LAW_LINEAR)
        {
            continue;
        }
        const size_t c = aenl_diagnose_dof_channel(base->type, (aenl_sim_dof_t)dof);
        for (size_t k = 0; k < sizeof(n_par) / sizeof(n_par[0]); ++k)
        {
            spec_t *s = &d->sp[d->n_sp++];
            memset(s, 0, sizeof(*s));
            s->effect = effects[k];
            s->dof = (aenl_sim_dof_t)dof;
            s->n_par = n_par[k];
            s->s = motion_scale(&d->x, c);
            s->m = r->chan[c].mean;
            s->p0 = r->sig_base[c].valid
                        ? -(r->sig_meas[c].quant[4] - r->sig_base[c].quant[4]) / s->s
                        : 0.0;
            s->best = HUGE_VAL;
        }
    }
}

/* Calibrate the candidates (grid, then Nelder-Mead: run_candidates), then the contenders' fits
 * once more (a fresh simplex: stage 3), so that the choice between them weighs their laws, not
 * how far each simplex got; d->order ranks them after. */
static aenl_status_t fit_candidates(diag_t *d, aenl_err_t *err)
{
    aenl_status_t st = run_candidates(&d->x, d->base, d->sp, d->n_sp, d->opts, err);
    if (st != AENL_OK)
    {
        return st;
    }
    /* Stage 3, the contenders (the best N_FLOOR_CAND): Nelder-Mead once more from the estimate
     * with a fresh simplex of the first steps. A simplex can collapse before it reaches the
     * minimum (its vertices fall into a lower-dimensional face, and its steps shrink without
     * leaving it); a fresh simplex around the estimate spans every direction again. */
    order_by_best(d->sp, d->n_sp, d->order);
    const size_t n_con = d->n_sp < N_FLOOR_CAND ? d->n_sp : N_FLOOR_CAND;
    st = refine_all(&d->x, d->base, d->sp, d->order, n_con, d->opts->max_evals,
                    "restarted %s %s: gap %.4g", err);
    order_by_best(d->sp, d->n_sp, d->order);
    return st;
}

/* The floors of the contenders, cand[i] for i < n, into fl[i], at once: each one's main run and
 * replicates on its own copy of the context. */
typedef struct
{
    const diag_t *d;
    const aenl_diagnose_cand_t *cand;
    floor_t *fl;
    unsigned *sims;
} floor_job_t;

static aenl_status_t floor_task(void *ctx, size_t i, aenl_err_t *err)
{
    const floor_job_t *j = (const floor_job_t *)ctx;
    ctx_t x = j->d->x;
    x.n_sims = 0;
    aenl_sim_model_t m = *j->d->base;
    m.law[j->cand[i].dof] = j->cand[i].law;
    aenl_diagnose_sig_t *ms = malloc(x.n_ch * sizeof(*ms));
    if (ms == NULL)
    {
        aenl_err_set(err, "out of memory (signatures)");
        return AENL_E_DIM;
    }
    aenl_status_t st = sim_sig(&x, &m, 0, ms, NULL, NULL, err);
    if (st == AENL_OK)
    {
        st = floor_of(&x, &m, ms, j->d->opts->n_replicates, &j->fl[i], NULL, err);
    }
    free(ms);
    j->sims[i] = x.n_sims;
    return st;
}

/* The result's candidates, best gap first, and the floors of the best N_FLOOR_CAND: the
 * common yardstick of the choice. A contender's floor goes into d->fl_cand[i], cd->floor and
 * cd->bounded; the common floors and the pooled relative variances take it in. */
static aenl_status_t rank_candidates(diag_t *d, aenl_err_t *err)
{
    aenl_diagnose_result_t *r = d->x.res;
    d->common = r->floor_before[d->x.n_ch];
    d->common_same = d->fl_base.same;
    memset(d->fl_cand, 0, sizeof(d->fl_cand));
    pool_rv(&d->fl_base, d->rv, d->n_rv);
    r->n_cand = d->n_sp;
    for (size_t i = 0; i < d->n_sp; ++i)
    {
        const spec_t *s = &d->sp[d->order[i]];
        aenl_diagnose_cand_t *cd = &r->cand[i];
        cd->effect = s->effect;
        cd->dof = s->dof;
        cd->n_params = s->n_par;
        spec_law(s, s->theta, &cd->law);
        cd->gap = sqrt(s->best);
        cd->n_evals = s->n_evals;
        cd->refined = i < d->opts->n_refine;
        cd->score = HUGE_VAL;
        cd->bounded = 1.0;
    }
    const size_t n_con = d->n_sp < N_FLOOR_CAND ? d->n_sp : N_FLOOR_CAND;
    unsigned sims[N_FLOOR_CAND] = {0};
    floor_job_t job = {d, r->cand, d->fl_cand, sims};
    const aenl_status_t st = aenl_parallel_try(n_con, floor_task, &job, err);
    for (size_t i = 0; i < d->n_sp && i < N_FLOOR_CAND && st == AENL_OK; ++i)
    {
        d->x.n_sims += sims[i];
        aenl_diagnose_cand_t *cd = &r->cand[i];
        cd->floor = d->fl_cand[i].ch[d->x.n_ch];
        cd->bounded = d->fl_cand[i].bounded;
        d->common = fmax(d->common, cd->floor);
        d->common_same = fmax(d->common_same, d->fl_cand[i].same);
        pool_rv(&d->fl_cand[i], d->rv, d->n_rv);
        advance(&d->x);
    }
    return st;
}

/* The scale of the floor the record follows. The replicates differ in their excitation
 * (turbulence) and noise; a record driven by the main run's own excitation (a known input, or a
 * simulation with the model's seed) differs from the right model by its noise only, a smaller
 * floor. Which of the two scales the record follows shows in the best gap, baseline's or a
 * candidate's (*g_min): nearer (in ratio) to the floor of the noise alone, the record shares
 * the excitation; so too when it is more than none_ratio times below the floor of other
 * turbulence, which no model can be against a record of other turbulence (a model that misses
 * by a bias b has gap^2 about floor^2 + b^2: where no candidate reaches the truth, the best gap
 * can be far from both floors). Then the scores are in units of that floor. In the larger one
 * every candidate that fits within it would score alike: on gust records with hysteresis
 * (delta 0.0019, alpha_f 0 in flap) the hysteresis' gap is 0.016 and a freeplay's 0.035, both
 * far inside the common floor 0.082. */
static void choose_scale(diag_t *d, double *g_min)
{
    aenl_diagnose_result_t *r = d->x.res;
    double common = fmax(d->common, AENL_DIAGNOSE_MIN_FLOOR);
    const double common_same = fmax(d->common_same, AENL_DIAGNOSE_MIN_FLOOR);
    double g = r->gap_before[d->x.n_ch];
    for (size_t i = 0; i < d->n_sp; ++i)
    {
        g = r->cand[i].bounded > 0.0 ? fmin(g, r->cand[i].gap) : g;
    }
    r->floor_same = common_same;
    r->excitation_shared =
        common_same < common && (g * g < common_same * common || g * d->opts->none_ratio < common);
    if (r->excitation_shared)
    {
        common = common_same;
    }
    r->common_floor = common;
    *g_min = g;
}

/* The gap's degrees of freedom M (2 / the relative variance of the squared gaps). The gap
 * squared over the floor's squared is about chi-square over M, whose relative variance 2 / M
 * the replicate pairs measure (pooled over the floors in the scale the record follows). A
 * parameter fitted to the record takes about one unit of chi-square off (penalty 2: Akaike's),
 * whatever M; in units of the floor squared that is 2 / M. On gust records with other
 * turbulence M comes out 8 to 75 (10 to 90 %; median 21), so a fixed 0.5 a parameter in units
 * of the floor squared would be 4 to 38 units: it names a freeplay on gust records whose
 * hysteresis fits better by less. No spread to measure (every run alike: no noise, no
 * turbulence): M from the baseline's runs given a nominal noise (nominal_rv). */
static aenl_status_t gap_dof(diag_t *d, double *m_rep, aenl_err_t *err)
{
    const int k_rv = d->x.res->excitation_shared ? 1 : 0;
    double *const rv = d->rv;
    size_t *const n_rv = d->n_rv;
    if (!(n_rv[k_rv] > 0u && rv[k_rv] > 0.0))
    {
        double rv_nom = (double)NAN;
        const aenl_status_t st = nominal_rv(&d->x, d->base, d->opts->n_replicates, &rv_nom, err);
        if (st != AENL_OK)
        {
            return st;
        }
        rv[k_rv] = isfinite(rv_nom) ? rv_nom : 0.0;
        n_rv[k_rv] = isfinite(rv_nom) ? 1u : 0u;
    }
    *m_rep = n_rv[k_rv] > 0u && rv[k_rv] > 0.0 ? 2.0 * (double)n_rv[k_rv] / rv[k_rv] : 1.0;
    return AENL_OK;
}

/* The scores in chi-square units and the best candidate (*best; n_sp when there is none).
 * Quasi-likelihood (QAIC): when even the best law misses the record beyond its floor, by a bias,
 * the squared gap's spread grows with that bias, and a difference between two such misfits is
 * worth less than the replicates' spread says. The chi-square is divided by the dispersion, the
 * best's (gap / F)^2 when above 1. Where every run is alike (F the least floor) that leaves
 * M (gap / best gap)^2 + penalty, M measured at the nominal noise: with M 1 there, a noise-free
 * decay with a freeplay names a preload 1.7 times the freeplay's gap (by 0.13); with the
 * measured 48 the freeplay wins by 88 (docs/diagnose.md). */
static aenl_status_t score_candidates(diag_t *d, size_t *best, aenl_err_t *err)
{
    aenl_diagnose_result_t *r = d->x.res;
    double g_min = 0.0, m_rep = 1.0;
    choose_scale(d, &g_min);
    const aenl_status_t st = gap_dof(d, &m_rep, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const double common = r->common_floor;
    r->dispersion = fmax(1.0, (g_min / common) * (g_min / common));
    r->m_eff = m_rep / r->dispersion;
    /* The gap's own test of the best law, at the summaries' level (0.1 %): M (gap / F)^2 within
     * the 99.9 % point of chi-square with M degrees of freedom. */
    r->gap_accepts = m_rep * r->dispersion <= chi2_quantile_999(m_rep);
    *best = d->n_sp;
    for (size_t i = 0; i < d->n_sp; ++i)
    {
        aenl_diagnose_cand_t *cd = &r->cand[i];
        /* a candidate none of whose runs stayed bounded cannot be the record's model */
        cd->score = cd->bounded > 0.0 ? r->m_eff * (cd->gap / common) * (cd->gap / common) +
                                            d->opts->penalty * cd->n_params - 2.0 * log(cd->bounded)
                                      : HUGE_VAL;
        if (*best == d->n_sp || cd->score < r->cand[*best].score)
        {
            *best = i;
        }
    }
    return AENL_OK;
}

/* Name the missing effect, cand[best], or none: beyond none_ratio times the baseline's floor
 * (in the scale the record follows) by the gap, or within it where the summaries reject the
 * baseline (test_baseline), a candidate that takes 30 % off the baseline's gap is named
 * (name_law). *moved: 1 when the summary fit moved the named law from the one whose floor was
 * measured. */
static aenl_status_t name_effect(diag_t *d, size_t best, int *moved, aenl_err_t *err)
{
    aenl_diagnose_result_t *r = d->x.res;
    const aenl_diagnose_opts_t *opts = d->opts;
    const size_t n_ch = d->x.n_ch, n_sp = d->n_sp;
    r->base_floor = r->excitation_shared ? d->fl_base.same : r->floor_before[n_ch];
    const double sig_total = r->gap_before[n_ch] / fmax(r->base_floor, AENL_DIAGNOSE_MIN_FLOOR);
    r->explained = 1;
    r->chosen = n_sp;
    r->rival = n_sp;
    r->rival_chi2 = (double)NAN;
    r->effect = AENL_DIAGNOSE_NONE;
    r->dof = AENL_SIM_DOF_PITCH;
    r->updated = *d->base;
    int name_one = sig_total > opts->none_ratio;
    *moved = 0;
    if (!name_one && opts->summary_records > 0u)
    {
        const aenl_status_t st = test_baseline(&d->x, d->base, opts, r, err);
        if (st != AENL_OK)
        {
            return st;
        }
        /* Within the floor by the gap, but the precise summaries reject the baseline: an effect
         * the gap's spread hides (a small law under turbulence). A candidate that takes 30 % off
         * the gap names it as any other; else none stands, and the report says the summaries
         * disagree. */
        name_one = aenl_diagnose_baseline_agrees(r) == 0;
    }
    if (!name_one || best >= n_sp)
    {
        return AENL_OK;
    }
    if (r->cand[best].gap < 0.7 * r->gap_before[n_ch])
    {
        return name_law(&d->x, d->base, opts, best, moved, err);
    }
    /* beyond the floor and nothing takes 30 % off: unexplained; within it (named only on the
     * summaries' word): none stands */
    r->explained = sig_total <= opts->none_ratio;
    return AENL_OK;
}

/* After: the updated model under the main seeds, its gap and its floor: the named candidate's
 * as measured among the contenders, unless the summary fit has moved its law (or it was not
 * among them): then its own floor again. */
static aenl_status_t measure_updated(diag_t *d, int moved, aenl_err_t *err)
{
    aenl_diagnose_result_t *r = d->x.res;
    const size_t n_ch = d->x.n_ch, n_sp = d->n_sp;
    /* the updated model (its INI, its report) starts where its own fit puts it */
    aenl_sim_model_t upd;
    aenl_status_t st = own_start(&d->x, &r->updated, &upd, &r->initial, err);
    if (st != AENL_OK)
    {
        return st;
    }
    r->updated = upd;
    st = sim_sig(&d->x, &r->updated, 0, r->sig_upd, r->y_upd, r->psd_upd, err);
    if (st != AENL_OK)
    {
        return st;
    }
    r->gap_after[n_ch] = gap_of(&d->x, r->sig_meas, r->sig_upd, r->gap_after, r->fam_after);
    if (r->chosen < n_sp)
    {
        r->cand[r->chosen].gap = r->gap_after[n_ch]; /* its final law */
    }
    const floor_t *fl_after = &d->fl_base;
    floor_t fl_extra;
    if (r->chosen < N_FLOOR_CAND && !moved)
    {
        fl_after = &d->fl_cand[r->chosen];
    }
    else if (r->chosen < n_sp)
    {
        st = floor_of(&d->x, &r->updated, r->sig_upd, d->opts->n_replicates, &fl_extra, NULL, err);
        if (st != AENL_OK)
        {
            return st;
        }
        fl_after = &fl_extra;
        r->cand[r->chosen].floor = fl_extra.ch[n_ch];
        r->cand[r->chosen].bounded = fl_extra.bounded;
    }
    memcpy(r->floor_after, fl_after->ch, sizeof(r->floor_after));
    set_sig(r, fl_after, r->fam_after, r->sig_after);
    return AENL_OK;
}

/* Measurement SNR of the record against the updated model's clean response (r->y_upd). */
static void measurement_snr(aenl_diagnose_result_t *r)
{
    const size_t n = r->n_samples;
    for (size_t c = 0; c < r->n_channels; ++c)
    {
        const aenl_diagnose_chan_t *ch = &r->chan[c];
        double m = 0.0, v = 0.0;
        const double *y = r->y_upd + c * n;
        int ok = 1;
        for (size_t i = 0; i < n; ++i)
        {
            ok = ok && isfinite(y[i]);
            m += y[i];
        }
        m /= (double)n;
        for (size_t i = 0; i < n; ++i)
        {
            v += (y[i] - m) * (y[i] - m);
        }
        v = v / (double)n - ch->noise_sd * ch->noise_sd;
        r->snr[c] = (ok && v > 0.0 && ch->noise_sd > 0.0) ? sqrt(v) / ch->noise_sd : 0.0;
    }
}

static aenl_status_t diagnose(const aenl_table_t *measured, const aenl_sim_model_t *base,
                              const aenl_sim_run_t *run, const aenl_diagnose_opts_t *opts,
                              aenl_diagnose_result_t *r, aenl_err_t *err)
{
    aenl_status_t st = check_unforced(run, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const double t0 = aenl_now_s();
    size_t n_ch = 0;
    const char *const *names = aenl_diagnose_channel_names(base->type, &n_ch);
    r->n_channels = n_ch;
    diag_t dg;
    memset(&dg, 0, sizeof(dg));
    diag_t *const d = &dg;
    d->base = base;
    d->opts = opts;
    st = setup_ctx(d, measured, run, names, r, err);
    if (st == AENL_OK)
    {
        st = measure_baseline(d, names, n_ch, err);
    }
    if (st == AENL_OK)
    {
        make_specs(d);
        /* the stages: the baseline, each candidate's grid, the refined ones, the contenders'
         * restarts and floors, the naming (with its summary fit), the updated model */
        const size_t n_con = d->n_sp < N_FLOOR_CAND ? d->n_sp : N_FLOOR_CAND;
        d->x.steps =
            3u + d->n_sp + (d->n_sp < opts->n_refine ? d->n_sp : opts->n_refine) + 2u * n_con;
        advance(&d->x);
        st = fit_candidates(d, err);
    }
    if (st == AENL_OK)
    {
        st = rank_candidates(d, err);
    }
    size_t best = 0;
    if (st == AENL_OK)
    {
        st = score_candidates(d, &best, err);
    }
    int moved = 0; /* the summary fit moved the named law from the one whose floor it has */
    if (st == AENL_OK)
    {
        st = name_effect(d, best, &moved, err);
        advance(&d->x);
    }
    if (st == AENL_OK)
    {
        st = measure_updated(d, moved, err);
    }
    if (st == AENL_OK)
    {
        d->x.step = d->x.steps - 1u;
        advance(&d->x);
        measurement_snr(r);
        r->n_sims = d->x.n_sims;
        r->seconds = aenl_now_s() - t0;
    }
    return st;
}

int aenl_diagnose_baseline_agrees(const aenl_diagnose_result_t *r)
{
    if (r->base_exact)
    {
        return 1;
    }
    if (r->base_test.n_rep == 0u)
    {
        return -1;
    }
    return r->base_test.p > AENL_DIAGNOSE_SUMTEST_LEVEL;
}

aenl_status_t aenl_diagnose_run(const aenl_table_t *measured, const aenl_sim_model_t *base,
                                const aenl_sim_run_t *run, const aenl_diagnose_opts_t *opts,
                                aenl_diagnose_result_t *out, aenl_err_t *err)
{
    memset(out, 0, sizeof(*out));
    if (measured == NULL || base == NULL || run == NULL || opts == NULL)
    {
        aenl_err_set(err, "diagnose: NULL argument");
        return AENL_E_ARG;
    }
    if (opts->n_replicates < 2u || opts->n_replicates > 16u || !(opts->penalty >= 0.0) ||
        !(opts->none_ratio > 0.0) || !(opts->report_ratio > 0.0) || opts->max_evals < 4u ||
        opts->n_refine > AENL_DIAGNOSE_MAX_CAND ||
        (opts->summary_records > 0u &&
         (opts->summary_records < 32u || opts->summary_records > 4096u)))
    {
        aenl_err_set(err, "diagnose: options out of range (replicates 2..16, penalty >= 0, "
                          "ratios > 0, max_evals >= 4, summary records 0 or 32..4096)");
        return AENL_E_ARG;
    }
    const aenl_status_t st = diagnose(measured, base, run, opts, out, err);
    if (st != AENL_OK)
    {
        aenl_diagnose_result_free(out);
    }
    return st;
}
