/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose.h
 * @brief Host-only: model-vs-measurement diagnosis. Given a measured record and a baseline model
 *        of the same test (velocity, initial condition or excitation, sampling), find where they
 *        disagree, name the structural effect the model lacks, add it with fitted parameters and
 *        show the gap shrink (docs/diagnose.md).
 *
 * Method (docs/diagnose.md has the full definitions):
 *  1. Signature settings are fixed once from the measured record, per channel: scale (std),
 *     measurement-noise std (robust, from third differences), dominant period (Welch peak),
 *     low-pass pre-filter (4 / period), lags (period / 16, / 8, / 4), a 32-node grid over the
 *     1..99 % quantiles, a kernel bandwidth of 2 grid steps, Welch segment and spectral bands.
 *  2. Signature of a channel: amplitude (9 quantiles and an 8-window RMS envelope), conditional
 *     mean and conditional standard deviation curves (rising and falling, 3 lags; the core
 *     estimator aenl_moments through aenl_curves), Welch spectrum in 20 log-spaced bands.
 *  3. Every simulation runs the model under the measured conditions, noise-free, then gets
 *     Gaussian noise of the measured noise std per channel. All candidate simulations share the
 *     same turbulence and noise seeds (common random numbers); replicates use other seeds.
 *  4. Gap per channel: RMS over the four signature families of each family's RMS normalised
 *     difference (quantiles, envelope and curves in units of the measured std, spectrum as
 *     ln amplitude ratio); total: RMS over channels. Noise floor: RMS of the gap between
 *     independent replicates of the same model that stayed bounded. The measurement noise the
 *     simulations get is what the record's high-frequency scale has beyond the baseline's own.
 *  5. Candidates per DOF whose baseline law is linear: freeplay (gap δ, start α_f), hysteresis
 *     (δ, α_f, M0), cubic polynomial (c3), quintic polynomial (c3, c5), preload (M0). Each is
 *     calibrated by a coarse grid,
 *     then Nelder-Mead on the total gap squared. Choice: "none" when the baseline gap is within
 *     `none_ratio` times its floor (unless the summaries reject the baseline); otherwise the
 *     least M (gap / floor)^2 + penalty * n_params - 2 ln(share of the candidate's runs that
 *     stayed bounded: the record did), a chi-square-like score: M = 2 / the relative variance
 *     of the replicate pairs' squared gaps, the gap's effective number of elements.
 *     The named effect is refitted to the record's summaries (aenl_diagnose_fit_summaries),
 *     and, where the gap accepts the best law, so are its rivals, the best of each other effect
 *     or DOF within penalty of the best score: the least chi2 + penalty * n_params of the fits
 *     the summaries do not reject is named (moment selection, Andrews & Lu 2001).
 *
 * Memory: the result owns heap arrays released by aenl_diagnose_result_free(). No global state;
 * re-entrant. Cost: a few hundred simulations of the record (docs/diagnose.md gives timings).
 */
#ifndef AENL_TOOLS_DIAGNOSE_H
#define AENL_TOOLS_DIAGNOSE_H

#include <stddef.h>
#include <stdint.h>

#include "aenl_tools/aenl_csv.h"
#include "aenl_tools/aenl_io.h"
#include "aenl_tools/aenl_progress.h"
#include "aenl_tools/aenl_sim.h"

#define AENL_DIAGNOSE_N_FAMILY 4  /**< amplitude, mean, std, spectrum */
#define AENL_DIAGNOSE_MAX_CAND 15 /**< 5 candidates x 3 DOFs */
#define AENL_DIAGNOSE_MAX_PAR  3  /**< parameters of one candidate */
#define AENL_DIAGNOSE_MAX_DIS  (AENL_SIM_MAX_Q * AENL_DIAGNOSE_N_FAMILY)
#define AENL_DIAGNOSE_N_QUANT  9    /**< amplitude quantiles */
#define AENL_DIAGNOSE_N_ENV    8    /**< envelope windows */
#define AENL_DIAGNOSE_N_GRID   32   /**< curve nodes */
#define AENL_DIAGNOSE_N_LAGS   3    /**< curve lags */
#define AENL_DIAGNOSE_N_BANDS  20   /**< spectral bands */
#define AENL_DIAGNOSE_N_CURVE  192  /**< 2 directions x N_LAGS x N_GRID */
#define AENL_DIAGNOSE_MAX_SEG  4096 /**< longest Welch segment */
#define AENL_DIAGNOSE_MAX_BINS 2049 /**< Welch bins: MAX_SEG / 2 + 1 */
/** Level of the baseline's summary test (aenl_diagnose_summary_test): the summaries reject the
 *  baseline when its p is at most this. */
#define AENL_DIAGNOSE_SUMTEST_LEVEL 0.05

/** The missing effect named by the diagnosis. */
typedef enum aenl_diagnose_effect
{
    AENL_DIAGNOSE_NONE = 0,
    AENL_DIAGNOSE_FREEPLAY = 1,
    AENL_DIAGNOSE_HYSTERESIS = 2,
    AENL_DIAGNOSE_POLYNOMIAL = 3,
    AENL_DIAGNOSE_PRELOAD = 4
} aenl_diagnose_effect_t;

/** Signature families. */
typedef enum aenl_diagnose_family
{
    AENL_DIAGNOSE_AMPLITUDE = 0, /**< quantiles and RMS envelope (LCO amplitude or decay) */
    AENL_DIAGNOSE_MEAN = 1,      /**< conditional mean curves */
    AENL_DIAGNOSE_STD = 2,       /**< conditional standard deviation curves */
    AENL_DIAGNOSE_SPECTRUM = 3   /**< Welch spectrum in bands */
} aenl_diagnose_family_t;

/** The baseline's initial state fitted to the record (aenl_diagnose_initial_fit): a free
 *  decay's release, which the test description cannot give exactly. */
typedef struct aenl_diagnose_initial
{
    int estimated; /**< 1: the baseline compared, and the updated model, start from the fit */
    size_t window; /**< samples fitted, the record's first: one period of the fastest mode; 0:
                        the baseline could not be fitted (it runs away there) and every model
                        starts from the record's first sample at rest, without errors */
    double x0_sd[AENL_SIM_N_DOF], v0_sd[AENL_SIM_N_DOF]; /**< standard errors, INI units */
    double rms; /**< the fit's residual RMS over the window, in channel stds */
} aenl_diagnose_initial_t;

/** Options (aenl_diagnose_opts_default). */
typedef struct aenl_diagnose_opts
{
    unsigned n_replicates; /**< replicates per noise-floor estimate, >= 2 (default 3) */
    double penalty;        /**< choice penalty per parameter, in chi-square units (2: AIC) */
    double none_ratio;     /**< baseline gap / floor at or below which "none" is named (2) */
    double report_ratio;   /**< a (channel, family) is reported when its gap / floor > this (3) */
    unsigned n_refine;     /**< candidates refined by Nelder-Mead after the grid (4) */
    unsigned max_evals;    /**< Nelder-Mead evaluations per candidate (40) */
    uint64_t noise_seed;   /**< seed of the simulated measurement noise (1) */
    unsigned summary_records; /**< records simulated for the summary fit of the named effect
                                   (aenl_diagnose_fit_summaries: a quarter for the
                                   sensitivities), 32..4096; 0: no summary fit (64) */
    int verbose;              /**< 1: progress lines on stderr */
    const char *time_column;  /**< the record's time column by name; NULL (default): the column
                                   aenl_csv_is_time_name knows */
    const aenl_progress_t *progress; /**< hears after each stage of the search: the baseline,
                                          each candidate's grid and refinement, each
                                          contender's restart and floor, the end (NULL:
                                          nobody) */
} aenl_diagnose_opts_t;

/** One calibrated candidate. */
typedef struct aenl_diagnose_cand
{
    aenl_diagnose_effect_t effect;
    aenl_sim_dof_t dof;
    unsigned n_params;
    aenl_sim_law_t law; /**< the fitted law of the DOF */
    double gap;         /**< total gap of the fitted model (main seeds) */
    double floor;       /**< its replicate floor (0 when not computed: not among the best) */
    double bounded;     /**< share of its runs (main seeds and replicates) that stayed bounded
                             under the record's conditions (1 when its floor was not computed) */
    double score;       /**< m_eff (gap / common floor)^2 + penalty * n_params - 2 ln bounded
                             (the log-likelihood of a record that stayed bounded); HUGE_VAL
                             unscored */
    unsigned n_evals;   /**< simulations spent */
    int refined;        /**< 1 when Nelder-Mead ran */
} aenl_diagnose_cand_t;

/** A significant disagreement of the baseline. */
typedef struct aenl_diagnose_dis
{
    size_t channel;                /**< output channel index */
    aenl_diagnose_family_t family; /**< signature */
    double lo, hi;                 /**< band: channel units, or frequency (spectrum) */
    double significance;           /**< family gap / its replicate floor */
} aenl_diagnose_dis_t;

/** Per-channel signature settings, fixed from the measured record (read-only). */
typedef struct aenl_diagnose_chan
{
    double scale;        /**< std of the measured channel */
    double noise_sd;     /**< measurement-noise std: noise_record, or what the record's third
                              differences have beyond the baseline's own response where that is
                              less (aenl_diagnose_run) */
    double noise_record; /**< the record's high-frequency scale (third differences): its
                              noise std if the response itself is smooth there */
    double mean;         /**< mean of the pre-filtered measured channel */
    double period;       /**< dominant period, samples */
    double cutoff;       /**< pre-filter cutoff, fraction of the sample rate */
    size_t settle;       /**< leading samples left out of every signature */
    uint16_t lags[AENL_DIAGNOSE_N_LAGS];
    double x_min, x_max, bandwidth; /**< curve grid and kernel bandwidth */
    size_t seg;                     /**< Welch segment length */
    size_t band_lo[AENL_DIAGNOSE_N_BANDS], band_hi[AENL_DIAGNOSE_N_BANDS]; /**< bins [lo, hi) */
    size_t n_bands;
} aenl_diagnose_chan_t;

/** Signature of one channel of one record. */
typedef struct aenl_diagnose_sig
{
    int valid; /**< 0: the record diverged, was not finite or never moved (every difference
                    capped) */
    double quant[AENL_DIAGNOSE_N_QUANT];
    double env[AENL_DIAGNOSE_N_ENV];
    double mean[AENL_DIAGNOSE_N_CURVE]; /**< [dir: rising, falling][lag][node], NaN empty */
    double sd[AENL_DIAGNOSE_N_CURVE];
    double weight[AENL_DIAGNOSE_N_CURVE]; /**< effective sample size, 0 empty */
    double lpsd[AENL_DIAGNOSE_N_BANDS];   /**< ln of the band-mean PSD */
    double freq;                          /**< dominant frequency, cycles per sample */
    double amp;                           /**< half of the 1..99 % quantile range */
} aenl_diagnose_sig_t;

/** Result of aenl_diagnose_summary_test(). */
typedef struct aenl_diagnose_sumtest
{
    double d2;      /**< the record's squared Mahalanobis distance from the pooled mean */
    double p;       /**< share of the n_rep + 1 records at least as far out as the record's */
    size_t d;       /**< summaries (8 a channel) */
    unsigned n_rep; /**< records of the model simulated (0: no test) */
} aenl_diagnose_sumtest_t;

/** Everything one diagnosis found. */
typedef struct aenl_diagnose_result
{
    size_t n_channels, n_samples;
    double dt; /**< sample step, model time unit */
    const char *names[AENL_SIM_MAX_Q];
    aenl_diagnose_chan_t chan[AENL_SIM_MAX_Q];
    /** gap per channel (index n_channels = total), before and after, with replicate floors */
    double gap_before[AENL_SIM_MAX_Q + 1], gap_after[AENL_SIM_MAX_Q + 1];
    double floor_before[AENL_SIM_MAX_Q + 1], floor_after[AENL_SIM_MAX_Q + 1];
    /** family gaps [channel][family] and their significance (gap / floor), before and after */
    double fam_before[AENL_SIM_MAX_Q][AENL_DIAGNOSE_N_FAMILY];
    double fam_after[AENL_SIM_MAX_Q][AENL_DIAGNOSE_N_FAMILY];
    double sig_before[AENL_SIM_MAX_Q][AENL_DIAGNOSE_N_FAMILY];
    double sig_after[AENL_SIM_MAX_Q][AENL_DIAGNOSE_N_FAMILY];
    aenl_diagnose_dis_t dis[AENL_DIAGNOSE_MAX_DIS];
    size_t n_dis;
    aenl_diagnose_cand_t cand[AENL_DIAGNOSE_MAX_CAND];
    size_t n_cand;
    aenl_diagnose_effect_t effect; /**< the named effect */
    aenl_sim_dof_t dof;            /**< its DOF (meaningless for NONE) */
    size_t chosen;                 /**< index into cand, or n_cand for NONE */
    int explained;                 /**< 0: significant disagreement no candidate reduces */
    /** 1: instead of the test of base_test, the baseline's runs are all alike (floor 0: no
     *  turbulence, a noise-free record) and reproduce the record within twice the least floor;
     *  it agrees, nothing random is left to rank. */
    int base_exact;
    double common_floor; /**< floor the candidates' scores are in units of (their largest):
                              floor_same when excitation_shared */
    double floor_same;   /**< the largest floor of runs that share the main run's excitation and
                              differ in their noise only (baseline's and the best candidates') */
    /** 1: the record follows the main run's excitation (a known input, or a simulation with the
     *  model's turbulence seed): the best gap is nearer, in ratio, to floor_same than to the
     *  floor of independent excitations, or more than none_ratio below the latter; the scores
     *  are then in units of floor_same. */
    int excitation_shared;
    /** 1: the gap accepts the best law at 0.1 %: M (least gap / common_floor)^2, M before the
     *  dispersion, within the 99.9 % point of chi-square with M degrees of freedom. Only then
     *  are the best score's rivals refitted to the summaries (rival). */
    int gap_accepts;
    /** Effective number of independent elements of the gap, 2 / the relative variance of the
     *  squared gaps of replicate pairs (pooled over the baseline's and the best candidates'
     *  floors in the scale the record follows; where every run is alike, over the baseline's
     *  runs given a nominal noise of 0.1 % of each channel's std): the scores are
     *  m_eff (gap / common_floor)^2 + penalty per parameter, in chi-square units. Divided by
     *  the dispersion (below). */
    double m_eff;
    /** The best law's (gap / common_floor)^2 when above 1, else 1: how far even the best misses
     *  the record beyond its floor (quasi-likelihood: the chi-square of the scores is divided by
     *  it). */
    double dispersion;
    /** The baseline's floor in the scale the record follows: floor_before[total], or the floor
     *  of its noise alone when excitation_shared. The gap before beyond none_ratio times it names
     *  an effect. */
    double base_floor;
    aenl_sim_model_t updated; /**< baseline plus the named effect */
    /** The updated model's initial state, when fitted to the record (every model compared is
     *  fitted alike, aenl_diagnose_initial_wanted): its value is updated's x0, v0. */
    aenl_diagnose_initial_t initial;
    aenl_sim_run_t run;         /**< conditions of the comparison (no noise) */
    double snr[AENL_SIM_MAX_Q]; /**< measured std / noise std per channel (for the INI) */
    /** Signatures of the measured record, the baseline and the updated model (main seeds). */
    aenl_diagnose_sig_t sig_meas[AENL_SIM_MAX_Q], sig_base[AENL_SIM_MAX_Q], sig_upd[AENL_SIM_MAX_Q];
    double *psd_meas, *psd_base, *psd_upd; /**< [channel][bin] Welch PSD, n_bins per channel */
    size_t n_bins;
    double *y_meas, *y_base, *y_upd; /**< [channel][sample] records (simulated ones noisy) */
    /** When the baseline agrees within none_ratio x its floor (and opts.summary_records > 0):
     *  the baseline's summary test (aenl_diagnose_summary_test with summary_records records),
     *  a second look with the precise summaries the gap weighs loosely; when they reject the
     *  baseline, a candidate that takes 30 % off its gap is named as beyond the floor.
     *  base_test.n_rep 0: not run, or the records were unusable. */
    aenl_diagnose_sumtest_t base_test;
    /** Summary fit (opts.summary_records > 0, an effect named): standard errors of the named
     *  effect's parameters, in the order of aenl_diagnose_param_errors and their units;
     *  INFINITY where not determined. */
    double param_sd[AENL_DIAGNOSE_MAX_PAR];
    size_t n_param_sd;       /**< their count (0: no summary fit) */
    double chi2_start, chi2; /**< weighted summary misfit before and after the summary fit */
    size_t chi2_dof;         /**< its degrees of freedom, summaries - parameters (0: none) */
    int summary_rejected;    /**< 1: chi2 beyond its 99.9 % point, the summaries reject the
                                  model; the gap's fit is kept and n_param_sd is 0 */
    int by_summaries;        /**< 1: the summaries named the rival of the best score */
    /** The named law's rival (summary fit, an effect named, gap_accepts): the least-score
     *  candidate of another effect or DOF within opts.penalty of the best score that also
     *  takes 30 % off the baseline's gap; both are refitted to the summaries and the least
     *  chi2 + penalty x parameters is named (a rejected fit loses to one that is not; either
     *  fit not run, or both rejected: the best score stands). Index into cand, n_cand when
     *  there is none. */
    size_t rival;
    double rival_chi2; /**< the rival's summary-fit chi2 (NaN: no rival, or its fit did not run) */
    size_t rival_chi2_dof; /**< its degrees of freedom */
    int rival_rejected;    /**< 1: the rival's chi2 beyond its 99.9 % point */
    unsigned n_sims;       /**< simulations run */
    double seconds;        /**< wall time */
} aenl_diagnose_result_t;

/** Defaults (see the field comments). Cannot fail. */
void aenl_diagnose_opts_default(aenl_diagnose_opts_t *o);

/** The baseline's summary test of r (r->base_test): 1 it ran and the summaries agree (p above
 *  AENL_DIAGNOSE_SUMTEST_LEVEL) or the baseline reproduces the record exactly (r->base_exact),
 *  0 it ran and they reject the baseline, -1 it did not run. */
int aenl_diagnose_baseline_agrees(const aenl_diagnose_result_t *r);

/** "freeplay", "hysteresis", "polynomial", "preload", "none". */
const char *aenl_diagnose_effect_name(aenl_diagnose_effect_t e);
/** "pitch", "plunge", "flap". */
const char *aenl_diagnose_dof_name(aenl_sim_dof_t d);
/** "amplitude", "conditional_mean", "conditional_std", "spectrum". */
const char *aenl_diagnose_family_name(aenl_diagnose_family_t f);
/** Output channel index of a DOF for the model type (e.g. pitch -> alpha). */
size_t aenl_diagnose_dof_channel(aenl_sim_type_t type, aenl_sim_dof_t dof);

/**
 * @brief Diagnose `measured` (columns: a time column and the model's output channels, by name;
 *        uniform step equal to run->dt) against the baseline `base` run under `run` (duration
 *        is replaced by the record's length; the run's noise settings are ignored: the noise is
 *        estimated from the record).
 * @param[out] out filled on success (free with aenl_diagnose_result_free); zeroed on failure
 * @return AENL_OK; AENL_E_ARG with a message for a record that does not fit the model (missing
 *         channel, wrong step, too short, constant, missing samples) or a baseline that cannot
 *         be simulated; AENL_E_DIM out of memory.
 */
aenl_status_t aenl_diagnose_run(const aenl_table_t *measured, const aenl_sim_model_t *base,
                                const aenl_sim_run_t *run, const aenl_diagnose_opts_t *opts,
                                aenl_diagnose_result_t *out, aenl_err_t *err);

/** Free and zero. Safe on a zeroed result. */
void aenl_diagnose_result_free(aenl_diagnose_result_t *r);

/**
 * @brief Write the updated model as an INI that `aenl simulate` runs as is: the baseline's
 *        parameters and laws, the named effect's section, the conditions of the record, and a
 *        [noise] section with the record's SNR. `source` names the inputs in a comment.
 * @return AENL_OK or AENL_E_IO.
 */
aenl_status_t aenl_diagnose_write_ini(const aenl_diagnose_result_t *r, const char *source,
                                      const char *path, aenl_err_t *err);

/**
 * @brief Write the figure data into `dir`: gaps.csv, curves_<ch>.csv, spectrum.csv,
 *        timeseries.csv, candidates.csv.
 * @return AENL_OK or AENL_E_IO.
 */
aenl_status_t aenl_diagnose_write_data(const aenl_diagnose_result_t *r, const char *dir,
                                       aenl_err_t *err);

/**
 * @brief The result as the JSON object of `aenl diagnose --json` (docs/diagnose.md), malloc'ed
 *        text; `updated_model` is the given path or null. NULL when out of memory.
 */
char *aenl_diagnose_json(const aenl_diagnose_result_t *r, const char *updated_path);

/**
 * @brief Human-readable report (what disagrees, the candidates, the evidence, the gaps).
 *        fp: an open stream.
 */
void aenl_diagnose_report(const aenl_diagnose_result_t *r, FILE *fp);

/* ---- signatures (exposed for tests and figures) ------------------------------------------ */

/**
 * @brief Fix the signature settings of one channel from the measured samples x[0..n-1].
 * @return AENL_OK; AENL_E_ARG when the channel is constant, not finite or too short.
 */
aenl_status_t aenl_diagnose_chan_setup(const double *x, size_t n, aenl_diagnose_chan_t *c,
                                       aenl_err_t *err);

/**
 * @brief Signature of x[0..n-1] under the settings c; psd (NULL or seg/2+1 values) receives
 *        the Welch PSD. A non-finite, diverged or constant record gives valid = 0.
 */
aenl_status_t aenl_diagnose_signature(const double *x, size_t n, const aenl_diagnose_chan_t *c,
                                      aenl_diagnose_sig_t *s, double *psd, aenl_err_t *err);

/**
 * @brief Family gaps between two signatures of one channel (a: reference, usually measured);
 *        fam[f] receives the family's RMS normalised difference (capped at 10 per element).
 *        Optional per-element outputs (NULL to skip): dq/denv/dcurve_mean/dcurve_sd/dband.
 * @return the channel gap sqrt(mean_f fam[f]^2).
 */
double aenl_diagnose_distance(const aenl_diagnose_chan_t *c, const aenl_diagnose_sig_t *a,
                              const aenl_diagnose_sig_t *b, double fam[AENL_DIAGNOSE_N_FAMILY]);

/** Frequency of the highest peak of the whole record's periodogram (mean removed, Hann window,
 *  zero-padded to at least 4n, parabola through the log power), cycles per sample: far finer
 *  than a Welch bin on a long limit cycle. AENL_E_ARG below 16 samples. */
aenl_status_t aenl_diagnose_peak_freq(const double *x, size_t n, double *freq, aenl_err_t *err);

/** Welch PSD of x (mean removed, Hann, 50 % overlap), seg a power of two; psd: seg/2+1. */
aenl_status_t aenl_diagnose_welch(const double *x, size_t n, size_t seg, double *psd,
                                  aenl_err_t *err);

/**
 * @brief Information floor of the parameters of `effect` in law `dof` of `model`, in records of
 *        the test `run`: the Cramér–Rao bound of an estimator that uses these summaries of each
 *        channel efficiently: mean, log std, log kurtosis, log peak frequency
 *        (aenl_diagnose_peak_freq), and the second and third harmonics relative to the
 *        fundamental (phase-free, in blocks of ten periods); the first tenth of each record is
 *        left out.
 *        - Records: `model` under `run` with fresh gust and noise seeds per record; measurement
 *          noise of std noise_sd[channel] (NULL: the run's own SNR noise).
 *        - Covariance: the summaries of n_rep records. Its inverse is unbiased by
 *          (n_rep - d - 2) / (n_rep - 1), d the summaries' count.
 *        - Sensitivities: central differences, each parameter moved by 10 % of its value, over
 *          the seeds of the first n_jac records (common random numbers). What their noise adds
 *          to the information on average is taken off again (estimated from the seed-to-seed
 *          spread), so noise does not pass for information.
 *        sd[k]: standard deviation of parameter k (its units), in the order of
 *        aenl_diagnose_param_errors; INFINITY for each parameter that takes part (above a tenth,
 *        magnitude-scaled) in a combination the summaries do not determine. *n_par: their count (0
 * for NONE). Costs n_rep + 2 n_jac n_par simulations.
 * @return AENL_OK; AENL_E_ARG when n_rep is outside 32..4096 or n_jac outside 2..n_rep;
 *         AENL_E_NUMERIC when a record cannot be simulated or is unusable, or the covariance is
 *         singular; AENL_E_DIM out of memory.
 */
aenl_status_t aenl_diagnose_bound(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                  aenl_diagnose_effect_t effect, aenl_sim_dof_t dof,
                                  const double *noise_sd, unsigned n_rep, unsigned n_jac,
                                  double sd[AENL_DIAGNOSE_MAX_PAR], size_t *n_par, aenl_err_t *err);

/** Result of aenl_diagnose_fit_summaries(). */
typedef struct aenl_diagnose_sumfit
{
    aenl_sim_law_t law;               /**< the fitted law of the DOF */
    double sd[AENL_DIAGNOSE_MAX_PAR]; /**< standard errors (INFINITY: not determined, as in
                                           aenl_diagnose_bound) */
    size_t n_par;                     /**< parameters (aenl_diagnose_param_errors order) */
    double chi2_start, chi2;          /**< weighted summary misfit at the start and at the end */
    size_t dof;                       /**< summaries minus parameters */
    unsigned n_sims;                  /**< simulations run */
} aenl_diagnose_sumfit_t;

/**
 * @brief Fit the parameters of `effect` in law `dof` to the summaries of the measured record
 *        (those of aenl_diagnose_bound) by Gauss-Newton from `start`, weighted by the inverse
 *        covariance of the summaries at `start`: the efficient estimator on these summaries
 *        (method of simulated moments). Sensitivities and covariance as in
 *        aenl_diagnose_bound (n_rep records, n_jac seeds), held fixed; each step's model is
 *        simulated with the n_jac seeds and kept only if it lowers the misfit (halved up to
 *        twice otherwise). y_meas: the record, [channel][sample], n samples, the model's
 *        channels. out->sd: the estimate's standard errors from the same information.
 * @return as aenl_diagnose_bound; AENL_E_ARG when the record's channels are not the model's.
 */
aenl_status_t aenl_diagnose_fit_summaries(const aenl_sim_model_t *start, const aenl_sim_run_t *run,
                                          aenl_diagnose_effect_t effect, aenl_sim_dof_t dof,
                                          const double *noise_sd, const double *y_meas, size_t n,
                                          unsigned n_rep, unsigned n_jac,
                                          aenl_diagnose_sumfit_t *out, aenl_err_t *err);

/**
 * @brief Does `model` under `run` account for the summaries of the record (those of
 *        aenl_diagnose_bound: mean, log std, log kurtosis, log peak frequency and the second and
 *        third harmonics of every channel)? A Monte Carlo test: n_rep records of the model with
 *        their own gust and noise seeds (measurement noise of std noise_sd[channel]) and the
 *        record are pooled; each one's squared Mahalanobis distance from the pooled mean under
 *        the pooled covariance is computed the same way, and p is the share of the n_rep + 1 at
 *        least as far out as the record. If the model is right the record is one more draw of the
 *        same kind, its rank is uniform and P(p <= k / (n_rep + 1)) = k / (n_rep + 1), whatever
 *        the summaries' distribution (the peak frequency and harmonics of gust records are far
 *        from Gaussian, which a Hotelling T^2 on them would need). y_meas: the record,
 *        [channel][sample], n samples, the model's channels.
 * @return AENL_OK; AENL_E_ARG when n_rep is outside 8 channels + 8..4096 or the record's
 *         channels are not the model's; AENL_E_NUMERIC when a record cannot be simulated or is
 *         unusable, or the covariance is singular; AENL_E_DIM out of memory.
 */
aenl_status_t aenl_diagnose_summary_test(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                         const double *noise_sd, const double *y_meas, size_t n,
                                         unsigned n_rep, aenl_diagnose_sumtest_t *out,
                                         aenl_err_t *err);

/**
 * @brief The parameters that define `effect`, in one order for every list of them (errors,
 *        standard errors, bounds): freeplay delta, alpha_f; hysteresis delta, alpha_f, preload;
 *        polynomial c3 (coeffs[2]); preload preload. Their count (0 for NONE).
 */
size_t aenl_diagnose_n_params(aenl_diagnose_effect_t effect);

/** The parameters of `effect` that `law` carries: aenl_diagnose_n_params, and for a polynomial
 *  law with a quintic term (n_coeffs >= 5) two, c3 then c5 (coeffs[4]). */
size_t aenl_diagnose_law_n_params(aenl_diagnose_effect_t effect, const aenl_sim_law_t *law);

/** Parameter k (< aenl_diagnose_law_n_params) of `effect` in `law`. */
double aenl_diagnose_param_get(const aenl_sim_law_t *law, aenl_diagnose_effect_t effect, size_t k);

/** Set parameter k (< aenl_diagnose_law_n_params) of `effect` in `law` to v (a polynomial's c5
 *  makes the law quintic). */
void aenl_diagnose_param_set(aenl_sim_law_t *law, aenl_diagnose_effect_t effect, size_t k,
                             double v);

/** Short name of parameter k of `effect` for reports: "delta", "alpha_f", "M0", "c3" or "c5". */
const char *aenl_diagnose_param_name(aenl_diagnose_effect_t effect, size_t k);

/**
 * @brief Relative errors |fit - truth| / |truth| of the parameters that define `effect`
 *        (freeplay: delta, alpha_f; hysteresis: delta, alpha_f, preload; polynomial: c3;
 *        preload: preload) into rel[0..]; returns their count (0 for NONE).
 */
size_t aenl_diagnose_param_errors(aenl_diagnose_effect_t effect, const aenl_sim_law_t *truth,
                                  const aenl_sim_law_t *fit, double rel[AENL_DIAGNOSE_MAX_PAR]);

#endif /* AENL_TOOLS_DIAGNOSE_H */
