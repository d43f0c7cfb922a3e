/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose_bound.c
 * @brief How well a hidden-effect case's records determine its parameters: the Cramér–Rao bound
 *        of an estimator that uses a fixed set of record summaries efficiently, from simulated
 *        replicates of the truth (covariance) and common-random-number finite differences
 *        (sensitivities). docs/diagnose.md ("Hidden-effect results") gives the summaries and the
 * numbers.
 */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_diagnose_internal.h"
#include "aenl_tools/aenl_parallel.h"
#include "aenl_tools/aenl_rng.h"

/* Summaries per channel: mean, log std, log kurtosis, log peak frequency, and the second and
 * third harmonics relative to the fundamental (real and imaginary parts, phase-free). */
#define N_SUM_CH 8u
#define N_SUM    ((size_t)N_SUM_CH * AENL_SIM_MAX_Q)

/* Parameter moves of the finite differences, relative to the truth's value. */
#define REL_STEP 0.1

/* A parameter whose (magnitude-scaled) component in an undetermined direction exceeds this
 * is reported as not determined. */
#define UNDETERMINED_SHARE 0.1

/* Summary fit: Gauss-Newton steps and trial evaluations at most. */
#define SUMFIT_STEPS 3u
#define SUMFIT_EVALS 5u

/* Harmonic blocks: this many periods of the peak frequency each. */
#define BLOCK_PERIODS 10.0

static const double k_two_pi = 6.28318530717958647692;

/* Second and third harmonics of y (mean mu removed) at frequency f (cycles per sample) relative
 * to the fundamental, with the fundamental's phase taken out block by block: sums over blocks
 * of H_q conj(u)^q, u = H_1 / |H_1|, over the sum of |H_1|. out: re2, im2, re3, im3. */
static void harmonics(const double *y, size_t n, double mu, double f, double out[4])
{
    size_t len = (size_t)(BLOCK_PERIODS / f);
    len = len < 16u ? 16u : (len > n ? n : len);
    double acc[4] = {0.0, 0.0, 0.0, 0.0}, a_sum = 0.0;
    for (size_t b = 0; b + len <= n; b += len)
    {
        double h[3][2] = {{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}};
        for (size_t j = b; j < b + len; ++j)
        {
            const double d = y[j] - mu;
            const double c1 = cos(k_two_pi * f * (double)j), s1 = -sin(k_two_pi * f * (double)j);
            const double c2 = c1 * c1 - s1 * s1, s2 = 2.0 * c1 * s1;
            const double c3 = c2 * c1 - s2 * s1, s3 = c2 * s1 + s2 * c1;
            h[0][0] += d * c1;
            h[0][1] += d * s1;
            h[1][0] += d * c2;
            h[1][1] += d * s2;
            h[2][0] += d * c3;
            h[2][1] += d * s3;
        }
        const double a1 = hypot(h[0][0], h[0][1]);
        if (!(a1 > 0.0))
        {
            continue;
        }
        const double ur = h[0][0] / a1, ui = -h[0][1] / a1; /* conj(u) */
        const double u2r = ur * ur - ui * ui, u2i = 2.0 * ur * ui;
        const double u3r = u2r * ur - u2i * ui, u3i = u2r * ui + u2i * ur;
        acc[0] += h[1][0] * u2r - h[1][1] * u2i;
        acc[1] += h[1][0] * u2i + h[1][1] * u2r;
        acc[2] += h[2][0] * u3r - h[2][1] * u3i;
        acc[3] += h[2][0] * u3i + h[2][1] * u3r;
        a_sum += a1;
    }
    for (int q = 0; q < 4; ++q)
    {
        out[q] = a_sum > 0.0 ? acc[q] / a_sum : 0.0;
    }
}

/* Summaries of a record y[c * n + i] (n_ch channels), the first tenth left out (start-up).
 * AENL_E_NUMERIC when a channel is constant or not finite. */
static aenl_status_t summarise(const double *y_all, size_t n_all, size_t n_ch, double *s,
                               size_t *n_s, aenl_err_t *err)
{
    const size_t skip = n_all / 10u, n = n_all - skip;
    size_t k = 0;
    aenl_status_t st = AENL_OK;
    for (size_t c = 0; c < n_ch && st == AENL_OK; ++c)
    {
        const double *y = y_all + c * n_all + skip;
        double mu = 0.0, v = 0.0, v4 = 0.0, f = 0.0;
        for (size_t i = 0; i < n; ++i)
        {
            mu += y[i];
        }
        mu /= (double)n;
        for (size_t i = 0; i < n; ++i)
        {
            const double d = (y[i] - mu) * (y[i] - mu);
            v += d;
            v4 += d * d;
        }
        v /= (double)n;
        v4 /= (double)n;
        st = aenl_diagnose_peak_freq(y, n, &f, err);
        if (st == AENL_OK && !(v > 0.0 && f > 0.0 && isfinite(mu) && isfinite(v4)))
        {
            aenl_err_set(err, "summaries: a record is constant or not finite");
            st = AENL_E_NUMERIC;
        }
        if (st == AENL_OK)
        {
            s[k++] = mu;
            s[k++] = 0.5 * log(v);
            s[k++] = log(v4 / (v * v));
            s[k++] = log(f);
            harmonics(y, n, mu, f, s + k);
            k += 4u;
        }
    }
    *n_s = k;
    return st;
}

/* Summaries of one simulated record of model m under run (its seeds set by the caller), with
 * measurement noise of std noise_sd[c] added (seeded by run->noise_seed; NULL: the run's own
 * SNR noise). AENL_E_NUMERIC: the record cannot be simulated or is not usable. */
static aenl_status_t summaries(const aenl_sim_model_t *m, const aenl_sim_run_t *run,
                               const double *noise_sd, double *s, size_t *n_s, aenl_err_t *err)
{
    aenl_sim_result_t r;
    aenl_sim_run_t rr = *run;
    if (noise_sd != NULL)
    {
        rr.snr = 0.0;
    }
    aenl_status_t st = aenl_sim_simulate(m, &rr, &r, err);
    if (st != AENL_OK)
    {
        return st == AENL_E_DIM ? st : AENL_E_NUMERIC;
    }
    if (noise_sd != NULL)
    {
        aenl_rng_t g;
        aenl_rng_seed(&g, run->noise_seed);
        for (size_t i = 0; i < r.n_channels * r.n_samples; ++i)
        {
            r.y[i] += noise_sd[i / r.n_samples] * aenl_rng_gauss(&g);
        }
    }
    st = summarise(r.y, r.n_samples, r.n_channels, s, n_s, err);
    aenl_sim_result_free(&r);
    return st;
}

/* Replicate q of the truth's test: its own gust and noise seeds. */
static aenl_sim_run_t replicate_run(const aenl_sim_run_t *run, unsigned q)
{
    aenl_sim_run_t out = *run;
    out.turb_seed = run->turb_seed + 7919u * (uint64_t)(q + 1u);
    out.noise_seed = run->noise_seed + 104729u * (uint64_t)(q + 1u);
    return out;
}

/* A batch of records whose summaries are independent of each other: record q is model[q]
 * under run[q]; its summaries go to s + q N_SUM. They are simulated at once, each into its own
 * slots; the status is the first failure in the order of q, as one after the other would
 * stop there, and *d the summaries a record. */
typedef struct
{
    const aenl_sim_model_t *const *model;
    const aenl_sim_run_t *run;
    const double *noise_sd;
    double *s;
    size_t *d;
} batch_t;

static aenl_status_t batch_task(void *ctx, size_t q, aenl_err_t *err)
{
    const batch_t *b = (const batch_t *)ctx;
    b->d[q] = 0;
    return summaries(b->model[q], &b->run[q], b->noise_sd, b->s + q * N_SUM, &b->d[q], err);
}

static aenl_status_t summaries_batch(const aenl_sim_model_t *const *model,
                                     const aenl_sim_run_t *run, const double *noise_sd, size_t n,
                                     double *s, size_t *d, aenl_err_t *err)
{
    const size_t n1 = n > 0u ? n : 1u;
    double *sq = calloc(n1 * N_SUM, sizeof(double));
    size_t *dq = calloc(n1, sizeof(*dq));
    aenl_status_t st = AENL_E_DIM;
    if (sq == NULL || dq == NULL)
    {
        aenl_err_set(err, "out of memory (summaries)");
    }
    else
    {
        batch_t b = {model, run, noise_sd, sq, dq};
        st = aenl_parallel_try(n, batch_task, &b, err);
    }
    for (size_t q = 0; q < n && st == AENL_OK; ++q)
    {
        *d = dq[q];
        memcpy(s + q * N_SUM, sq + q * N_SUM, N_SUM * sizeof(double));
    }
    free(sq);
    free(dq);
    return st;
}

/* The summaries of `model` under the runs of replicates 0..n-1 into s + q N_SUM (a batch). */
static aenl_status_t model_summaries(const aenl_sim_model_t *model, const aenl_sim_run_t *run_in,
                                     const double *noise_sd, unsigned n, double *s, size_t *d,
                                     aenl_err_t *err)
{
    const aenl_sim_model_t **mq = malloc((n > 0u ? n : 1u) * sizeof(const aenl_sim_model_t *));
    aenl_sim_run_t *rq = malloc((n > 0u ? n : 1u) * sizeof(*rq));
    aenl_status_t st = AENL_E_DIM;
    if (mq == NULL || rq == NULL)
    {
        aenl_err_set(err, "out of memory (summaries)");
    }
    else
    {
        for (unsigned q = 0; q < n; ++q)
        {
            mq[q] = model;
            rq[q] = replicate_run(run_in, q);
        }
        st = summaries_batch(mq, rq, noise_sd, n, s, d, err);
    }
    free(mq);
    free(rq);
    return st;
}

/* Mean and covariance cov (d x d, unbiased) of the rows s[q * N_SUM + 0..d-1], q < n_rows;
 * mean and cov start at zero. */
static void row_moments(const double *s, size_t n_rows, size_t d, double *mean, double *cov)
{
    for (size_t q = 0; q < n_rows; ++q)
    {
        for (size_t i = 0; i < d; ++i)
        {
            mean[i] += s[q * N_SUM + i] / (double)n_rows;
        }
    }
    for (size_t q = 0; q < n_rows; ++q)
    {
        const double *sq = s + q * N_SUM;
        for (size_t i = 0; i < d; ++i)
        {
            for (size_t j = 0; j < d; ++j)
            {
                cov[i * d + j] += (sq[i] - mean[i]) * (sq[j] - mean[j]) / (double)(n_rows - 1u);
            }
        }
    }
}

/* Summaries of n_rep records of `model` (replicate seeds 0..n_rep-1) into s[q * N_SUM + i];
 * *d: summaries a record. */
static aenl_status_t replicate_summaries(const aenl_sim_model_t *model,
                                         const aenl_sim_run_t *run_in, const double *noise_sd,
                                         unsigned n_rep, double *s, size_t *d, aenl_err_t *err)
{
    return model_summaries(model, run_in, noise_sd, n_rep, s, d, err);
}

/* What the summaries say about the parameters at `model`: Cholesky factor of their covariance
 * (one record), the mean sensitivities, the mean summaries over the first n_jac seeds, and the
 * Fisher information with the noise of the sensitivities taken off. */
typedef struct
{
    size_t np, d;
    double chol[N_SUM * N_SUM];                /* upper Cholesky factor of the covariance */
    double jac[N_SUM * AENL_DIAGNOSE_MAX_PAR]; /* d x np */
    double centre[N_SUM];                      /* mean summaries of the first n_jac records */
    double fisher[AENL_DIAGNOSE_MAX_PAR * AENL_DIAGNOSE_MAX_PAR];
    double unbias; /* (n_rep - d - 2) / (n_rep - 1) */
} info_t;

/* Sensitivities of the summaries to the np parameters of the law: central differences over the
 * seeds of the first n_jac replicates, per seed (jq[q][i][k]) and their mean (jac, d x np, from
 * zero). The 2 np n_jac records are one batch, taken in the order parameter, seed, sign. */
static aenl_status_t sensitivities(const aenl_sim_model_t *model, const aenl_sim_run_t *run_in,
                                   aenl_diagnose_effect_t effect, aenl_sim_dof_t dof,
                                   const double *noise_sd, unsigned n_jac, size_t d, double *jq,
                                   double *jac, aenl_err_t *err)
{
    const size_t np = aenl_diagnose_law_n_params(effect, &model->law[dof]);
    const size_t n = 2u * np * n_jac;
    aenl_sim_model_t mpm[2u * AENL_DIAGNOSE_MAX_PAR];
    double h[AENL_DIAGNOSE_MAX_PAR] = {0.0};
    for (size_t k = 0; k < np; ++k)
    {
        const double v = aenl_diagnose_param_get(&model->law[dof], effect, k);
        h[k] = REL_STEP * fmax(fabs(v), 1e-12);
        mpm[2u * k] = *model;
        mpm[2u * k + 1u] = *model;
        aenl_diagnose_param_set(&mpm[2u * k].law[dof], effect, k, v + h[k]);
        aenl_diagnose_param_set(&mpm[2u * k + 1u].law[dof], effect, k, v - h[k]);
    }
    const aenl_sim_model_t **mq = malloc((n > 0u ? n : 1u) * sizeof(const aenl_sim_model_t *));
    aenl_sim_run_t *rq = malloc((n > 0u ? n : 1u) * sizeof(*rq));
    double *sq = calloc((n > 0u ? n : 1u) * N_SUM, sizeof(double));
    aenl_status_t st = AENL_E_DIM;
    if (mq == NULL || rq == NULL || sq == NULL)
    {
        aenl_err_set(err, "out of memory (summaries)");
    }
    else
    {
        for (size_t t = 0; t < n; ++t)
        {
            const size_t k = t / (2u * (size_t)n_jac), q = (t / 2u) % n_jac;
            mq[t] = &mpm[2u * k + t % 2u];
            rq[t] = replicate_run(run_in, (unsigned)q);
        }
        size_t dd = 0;
        st = summaries_batch(mq, rq, noise_sd, n, sq, &dd, err);
    }
    for (size_t k = 0; k < np && st == AENL_OK; ++k)
    {
        for (unsigned q = 0; q < n_jac; ++q)
        {
            const double *sp = sq + (2u * (k * n_jac + q)) * N_SUM;
            const double *sm = sp + N_SUM;
            for (size_t i = 0; i < d; ++i)
            {
                const double g = (sp[i] - sm[i]) / (2.0 * h[k]);
                jq[((size_t)q * d + i) * np + k] = g;
                jac[i * np + k] += g / (double)n_jac;
            }
        }
    }
    free(mq);
    free(rq);
    free(sq);
    return st;
}

static aenl_status_t information(const aenl_sim_model_t *model, const aenl_sim_run_t *run_in,
                                 aenl_diagnose_effect_t effect, aenl_sim_dof_t dof,
                                 const double *noise_sd, unsigned n_rep, unsigned n_jac,
                                 info_t *inf, aenl_err_t *err)
{
    memset(inf, 0, sizeof(*inf));
    const size_t np = aenl_diagnose_law_n_params(effect, &model->law[dof]);
    inf->np = np;
    if (np == 0u)
    {
        return AENL_OK;
    }
    if (n_jac < 2u || n_jac > n_rep || n_rep < N_SUM + 8u || n_rep > 4096u)
    {
        aenl_err_set(err, "summaries: %u records (%zu..4096) and %u for the sensitivities (2..)",
                     n_rep, N_SUM + 8u, n_jac);
        return AENL_E_ARG;
    }
    double *s = malloc((size_t)n_rep * N_SUM * sizeof(double));
    double *cov = inf->chol;
    double *jac = inf->jac;
    double *jq = malloc((size_t)n_jac * N_SUM * AENL_DIAGNOSE_MAX_PAR * sizeof(double));
    if (s == NULL || jq == NULL)
    {
        free(s);
        free(jq);
        aenl_err_set(err, "out of memory (summaries)");
        return AENL_E_DIM;
    }
    size_t d = 0;
    aenl_status_t st = replicate_summaries(model, run_in, noise_sd, n_rep, s, &d, err);
    inf->d = d;
    if (st == AENL_OK)
    {
        double mean[N_SUM] = {0.0};
        row_moments(s, n_rep, d, mean, cov); /* one record's covariance (symmetric) */
    }
    for (unsigned q = 0; q < n_jac && st == AENL_OK; ++q)
    {
        for (size_t i = 0; i < d; ++i)
        {
            inf->centre[i] += s[(size_t)q * N_SUM + i] / (double)n_jac;
        }
    }
    /* Sensitivities: central differences over the first n_jac replicates' seeds, per seed
     * (jq[q][i][k]) and their mean (jac). */
    if (st == AENL_OK)
    {
        st = sensitivities(model, run_in, effect, dof, noise_sd, n_jac, d, jq, jac, err);
    }
    /* Fisher information J' S^-1 J with the unbiased inverse (factor (n - d - 2) / (n - 1)),
     * less what the noise of the mean sensitivities adds to it on average. */
    const double unbias = (double)(n_rep - d - 2u) / (double)(n_rep - 1u);
    double *fi = inf->fisher;
    inf->unbias = unbias;
    if (st == AENL_OK &&
        LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'U', (lapack_int)d, cov, (lapack_int)d) != 0)
    {
        aenl_err_set(err, "summaries: their covariance is singular");
        st = AENL_E_NUMERIC;
    }
    for (unsigned q = 0; q <= n_jac && st == AENL_OK; ++q)
    {
        /* q < n_jac: a seed's deviation from the mean; q == n_jac: the mean itself */
        double dj[N_SUM * AENL_DIAGNOSE_MAX_PAR] = {0.0}, x[N_SUM * AENL_DIAGNOSE_MAX_PAR] = {0.0};
        for (size_t i = 0; i < d * np; ++i)
        {
            dj[i] = q < n_jac ? jq[(size_t)q * d * np + i] - jac[i] : jac[i];
        }
        memcpy(x, dj, d * np * sizeof(double));
        (void)LAPACKE_dpotrs(LAPACK_ROW_MAJOR, 'U', (lapack_int)d, (lapack_int)np, cov,
                             (lapack_int)d, x, (lapack_int)np);
        const double w = q < n_jac ? -unbias / ((double)n_jac * (double)(n_jac - 1u)) : unbias;
        for (size_t a = 0; a < np; ++a)
        {
            for (size_t b = 0; b < np; ++b)
            {
                for (size_t i = 0; i < d; ++i)
                {
                    fi[a * np + b] += w * dj[i * np + a] * x[i * np + b];
                }
            }
        }
    }
    free(jq);
    free(s);
    return st;
}

/* Standard deviations from the Fisher information, times sqrt(scale), into sd[0..np).
 * The information is scaled by the parameters' magnitudes (in `law`) and split into
 * eigen-directions: a direction without positive information is not determined, and every
 * parameter that takes part in it (a component above UNDETERMINED_SHARE) gets INFINITY; the
 * others their variance over the determined directions. */
static void fisher_sd(const info_t *inf, const aenl_sim_law_t *law, aenl_diagnose_effect_t effect,
                      double scale, double *sd)
{
    const size_t np = inf->np;
    double f[AENL_DIAGNOSE_MAX_PAR * AENL_DIAGNOSE_MAX_PAR], ev[AENL_DIAGNOSE_MAX_PAR];
    double mag[AENL_DIAGNOSE_MAX_PAR];
    for (size_t a = 0; a < np; ++a)
    {
        mag[a] = fmax(fabs(aenl_diagnose_param_get(law, effect, a)), 1e-300);
    }
    for (size_t a = 0; a < np; ++a)
    {
        for (size_t b = 0; b < np; ++b)
        {
            f[a * np + b] = inf->fisher[a * np + b] * mag[a] * mag[b];
        }
    }
    if (LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'V', 'U', (lapack_int)np, f, (lapack_int)np, ev) != 0)
    {
        for (size_t k = 0; k < np; ++k)
        {
            sd[k] = (double)INFINITY;
        }
        return;
    }
    const double top = ev[np - 1u]; /* ascending */
    for (size_t k = 0; k < np; ++k)
    {
        double var = 0.0;
        int free_dir = !(top > 0.0);
        for (size_t e = 0; e < np; ++e)
        {
            const double v = f[k * np + e]; /* component k of eigenvector e */
            if (ev[e] > 1e-12 * top)
            {
                var += v * v / ev[e];
            }
            else if (fabs(v) > UNDETERMINED_SHARE)
            {
                free_dir = 1;
            }
        }
        sd[k] = free_dir ? (double)INFINITY : mag[k] * sqrt(var * scale);
    }
}

aenl_status_t aenl_diagnose_bound(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                  aenl_diagnose_effect_t effect, aenl_sim_dof_t dof,
                                  const double *noise_sd, unsigned n_rep, unsigned n_jac,
                                  double sd_out[AENL_DIAGNOSE_MAX_PAR], size_t *n_par,
                                  aenl_err_t *err)
{
    info_t *inf = malloc(sizeof(*inf));
    if (inf == NULL)
    {
        aenl_err_set(err, "out of memory (summaries)");
        return AENL_E_DIM;
    }
    const aenl_status_t st = information(model, run, effect, dof, noise_sd, n_rep, n_jac, inf, err);
    *n_par = inf->np;
    if (st == AENL_OK && inf->np > 0u)
    {
        fisher_sd(inf, &model->law[dof], effect, 1.0, sd_out);
    }
    free(inf);
    return st;
}

/* Weighted residual norm r' S^-1 r of summaries r (d of them; chol: S's upper Cholesky
 * factor), times w. */
static double quad(const double *chol, size_t d, const double *r, double w)
{
    double x[N_SUM] = {0.0};
    memcpy(x, r, d * sizeof(double));
    (void)LAPACKE_dpotrs(LAPACK_ROW_MAJOR, 'U', (lapack_int)d, 1, chol, (lapack_int)d, x, 1);
    double q = 0.0;
    for (size_t i = 0; i < d; ++i)
    {
        q += r[i] * x[i];
    }
    return w * q;
}

/* Mean summaries of `m` over the first n_jac records' seeds. */
static aenl_status_t centre_of(const aenl_sim_model_t *m, const aenl_sim_run_t *run_in,
                               const double *noise_sd, unsigned n_jac, size_t d, double *centre,
                               aenl_err_t *err)
{
    memset(centre, 0, d * sizeof(double));
    double *sq = calloc((n_jac > 0u ? n_jac : 1u) * N_SUM, sizeof(double));
    if (sq == NULL)
    {
        aenl_err_set(err, "out of memory (summaries)");
        return AENL_E_DIM;
    }
    size_t dq = 0;
    const aenl_status_t st = model_summaries(m, run_in, noise_sd, n_jac, sq, &dq, err);
    for (unsigned q = 0; q < n_jac && st == AENL_OK; ++q)
    {
        for (size_t i = 0; i < d; ++i)
        {
            centre[i] += sq[(size_t)q * N_SUM + i] / (double)n_jac;
        }
    }
    free(sq);
    return st;
}

aenl_status_t aenl_diagnose_fit_summaries(const aenl_sim_model_t *start, const aenl_sim_run_t *run,
                                          aenl_diagnose_effect_t effect, aenl_sim_dof_t dof,
                                          const double *noise_sd, const double *y_meas, size_t n,
                                          unsigned n_rep, unsigned n_jac,
                                          aenl_diagnose_sumfit_t *out, aenl_err_t *err)
{
    memset(out, 0, sizeof(*out));
    out->law = start->law[dof];
    info_t *inf = malloc(sizeof(*inf));
    if (inf == NULL)
    {
        aenl_err_set(err, "out of memory (summaries)");
        return AENL_E_DIM;
    }
    aenl_status_t st = information(start, run, effect, dof, noise_sd, n_rep, n_jac, inf, err);
    const size_t np = inf->np, d = inf->d;
    out->n_par = np;
    double s_meas[N_SUM] = {0.0};
    size_t dm = 0;
    if (st == AENL_OK && np > 0u)
    {
        st = summarise(y_meas, n, d / N_SUM_CH, s_meas, &dm, err);
        if (st == AENL_OK && dm != d)
        {
            aenl_err_set(err, "summaries: the record has %zu, the model %zu", dm, d);
            st = AENL_E_ARG;
        }
    }
    if (st != AENL_OK || np == 0u)
    {
        free(inf);
        return st;
    }
    /* The residual's variance: one record's covariance plus that of a mean of n_jac. */
    const double w = inf->unbias / (1.0 + 1.0 / (double)n_jac);
    /* Gauss-Newton matrix J' S^-1 J (plain: positive definite) and its Cholesky factor. */
    double x[N_SUM * AENL_DIAGNOSE_MAX_PAR] = {0.0};
    double h[AENL_DIAGNOSE_MAX_PAR * AENL_DIAGNOSE_MAX_PAR] = {0.0};
    memcpy(x, inf->jac, d * np * sizeof(double));
    (void)LAPACKE_dpotrs(LAPACK_ROW_MAJOR, 'U', (lapack_int)d, (lapack_int)np, inf->chol,
                         (lapack_int)d, x, (lapack_int)np);
    for (size_t a = 0; a < np; ++a)
    {
        for (size_t b = 0; b < np; ++b)
        {
            double acc = 0.0;
            for (size_t i = 0; i < d; ++i)
            {
                acc += inf->jac[i * np + a] * x[i * np + b];
            }
            h[a * np + b] = acc;
        }
    }
    const int h_ok = LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'U', (lapack_int)np, h, (lapack_int)np) == 0;
    aenl_sim_model_t cur = *start;
    double r[N_SUM] = {0.0}, centre[N_SUM] = {0.0};
    memcpy(centre, inf->centre, d * sizeof(double));
    for (size_t i = 0; i < d; ++i)
    {
        r[i] = s_meas[i] - centre[i];
    }
    out->chi2_start = quad(inf->chol, d, r, w);
    double q_cur = out->chi2_start;
    unsigned evals = 0;
    for (unsigned it = 0; it < SUMFIT_STEPS && h_ok && st == AENL_OK; ++it)
    {
        /* step = (J' S^-1 J)^-1 J' S^-1 r, J fixed at the start (chord iterations) */
        double g[AENL_DIAGNOSE_MAX_PAR] = {0.0};
        for (size_t a = 0; a < np; ++a)
        {
            for (size_t i = 0; i < d; ++i)
            {
                g[a] += x[i * np + a] * r[i];
            }
        }
        (void)LAPACKE_dpotrs(LAPACK_ROW_MAJOR, 'U', (lapack_int)np, 1, h, (lapack_int)np, g, 1);
        int accepted = 0;
        for (unsigned half = 0; half < 3u && !accepted && evals < SUMFIT_EVALS; ++half)
        {
            const double lam = ldexp(1.0, -(int)half); /* 1, 1/2, 1/4 */
            aenl_sim_model_t trial = cur;
            int valid = 1;
            for (size_t k = 0; k < np; ++k)
            {
                const double p = aenl_diagnose_param_get(&trial.law[dof], effect, k);
                const double v = p + lam * g[k];
                /* a gap width stays positive: at most a fivefold shrink per step */
                valid = valid && (k > 0u || effect == AENL_DIAGNOSE_POLYNOMIAL ||
                                  effect == AENL_DIAGNOSE_PRELOAD || v > 0.2 * p);
                aenl_diagnose_param_set(&trial.law[dof], effect, k, v);
            }
            if (!valid)
            {
                continue;
            }
            double c_t[N_SUM] = {0.0}, r_t[N_SUM] = {0.0};
            ++evals;
            const aenl_status_t s_t = centre_of(&trial, run, noise_sd, n_jac, d, c_t, err);
            if (s_t == AENL_E_DIM)
            {
                st = s_t;
                break;
            }
            if (s_t != AENL_OK)
            {
                continue; /* the trial diverges: a shorter step */
            }
            for (size_t i = 0; i < d; ++i)
            {
                r_t[i] = s_meas[i] - c_t[i];
            }
            const double q_t = quad(inf->chol, d, r_t, w);
            if (q_t < q_cur)
            {
                accepted = 1;
                cur = trial;
                q_cur = q_t;
                memcpy(r, r_t, d * sizeof(double));
            }
        }
        if (!accepted)
        {
            break;
        }
    }
    out->law = cur.law[dof];
    out->chi2 = q_cur;
    out->dof = d - np;
    out->n_sims = n_rep + 2u * n_jac * (unsigned)np + evals * n_jac;
    if (st == AENL_OK)
    {
        fisher_sd(inf, &start->law[dof], effect, 1.0 + 1.0 / (double)n_jac, out->sd);
    }
    free(inf);
    return st;
}

aenl_status_t aenl_diagnose_summary_test(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                         const double *noise_sd, const double *y_meas, size_t n,
                                         unsigned n_rep, aenl_diagnose_sumtest_t *out,
                                         aenl_err_t *err)
{
    memset(out, 0, sizeof(*out));
    const size_t n_ch = model->type == AENL_SIM_AIRFOIL2DOF ? 2u : 3u;
    if (n_rep < n_ch * N_SUM_CH + 8u || n_rep > 4096u)
    {
        aenl_err_set(err, "summary test: %u records (%zu..4096)", n_rep, n_ch * N_SUM_CH + 8u);
        return AENL_E_ARG;
    }
    /* rows 0..n_rep-1 the model's records, row n_rep the record's */
    const size_t n_all = (size_t)n_rep + 1u;
    double *s = malloc(n_all * N_SUM * sizeof(double));
    double *cov = calloc(N_SUM * N_SUM, sizeof(double));
    double *d2 = malloc(n_all * sizeof(double));
    if (s == NULL || cov == NULL || d2 == NULL)
    {
        free(s);
        free(cov);
        free(d2);
        aenl_err_set(err, "out of memory (summaries)");
        return AENL_E_DIM;
    }
    size_t d = 0, dm = 0;
    double mean[N_SUM] = {0.0};
    aenl_status_t st = replicate_summaries(model, run, noise_sd, n_rep, s, &d, err);
    if (st == AENL_OK)
    {
        st = summarise(y_meas, n, n_ch, s + (size_t)n_rep * N_SUM, &dm, err);
    }
    if (st == AENL_OK && dm != d)
    {
        aenl_err_set(err, "summaries: the record has %zu, the model %zu", dm, d);
        st = AENL_E_ARG;
    }
    if (st == AENL_OK)
    {
        /* The pooled mean and covariance of all n_rep + 1, the record's included, so that every
         * record is treated alike. */
        row_moments(s, n_all, d, mean, cov);
        if (LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'U', (lapack_int)d, cov, (lapack_int)d) != 0)
        {
            aenl_err_set(err, "summaries: their covariance is singular");
            st = AENL_E_NUMERIC;
        }
    }
    if (st == AENL_OK)
    {
        for (size_t q = 0; q < n_all; ++q)
        {
            double r[N_SUM] = {0.0};
            for (size_t i = 0; i < d; ++i)
            {
                r[i] = s[q * N_SUM + i] - mean[i];
            }
            d2[q] = quad(cov, d, r, 1.0);
        }
        size_t at_least = 0;
        for (size_t q = 0; q < n_all; ++q)
        {
            at_least += d2[q] >= d2[n_rep];
        }
        out->d2 = d2[n_rep];
        out->d = d;
        out->n_rep = n_rep;
        out->p = (double)at_least / (double)n_all;
    }
    free(d2);
    free(cov);
    free(s);
    return st;
}
