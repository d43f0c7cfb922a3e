/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_identify.h
 * @brief Host pipeline of `aenl identify`: per channel, two streaming passes over a record and the
 *        core classifier (aenl_classifier.h) on the resulting moments.
 *
 * Pass 1 (streaming, O(1) memory per channel): count, range, mean and variance, the dominant
 * period from mean crossings with hysteresis, the white-noise level from the variance of
 * differences, and a bounded block of samples (at most opts.cv_max) for the bandwidth.
 * Then per channel: low-pass pre-filter at 8 / period (aenl_filter) unless turned off, lags
 * geometric from 1 to period / 8, bandwidth by leave-one-out cross-validation on the block unless
 * given, grid spacing = bandwidth over the range of the filtered signal.
 * Pass 2 (streaming): filter and push every sample into the channel's moments (direction split on)
 * and into a display estimator with the paper's lags 1, 10, 30; the classifier reads the former.
 * The same pass feeds the multi-channel restoring-force regression (aenl_rfs.h) through one
 * common low-pass at 5 / (shortest period), each channel first dithered up to a noise floor of
 * 0.1 of its standard deviation when it is cleaner than that (dither_std).
 * Memory does not grow with the record's length.
 * Verdict: when the regression finds a law in some channel, it decides: every channel it judged
 * takes its class, and the channel named is the nonlinear one with the largest t (a law another
 * channel's explains is an echo and linear). When it finds none anywhere, a train of kicked
 * decays is linear (decay_train), and otherwise the core classifier's verdicts stand (the
 * regression does not run on a single channel or a periodic record); a limit cycle the core
 * calls linear is polynomial (limit_cycle).
 */
#ifndef AENL_TOOLS_IDENTIFY_H
#define AENL_TOOLS_IDENTIFY_H

#include <stddef.h>
#include <stdio.h>
#include <stdint.h>

#include "aenl/aenl.h"
#include "aenl_tools/aenl_diagnose.h"
#include "aenl_tools/aenl_io.h"
#include "aenl_tools/aenl_plot.h"
#include "aenl_tools/aenl_rfs.h"

/** A record read twice, one row at a time (a CSV file or arrays in memory). */
typedef struct aenl_identify_source
{
    size_t n_cols;            /**< channels (the time column excluded) */
    const char *const *names; /**< n_cols channel names */
    void *ctx;
    /** Start (or restart) reading; AENL_OK or an error with err set. */
    aenl_status_t (*open)(void *ctx, aenl_err_t *err);
    /** Next row into row[n_cols]: 1 a row, 0 end, -1 error (err set). */
    int (*next)(void *ctx, double *row, aenl_err_t *err);
    void (*close)(void *ctx);
} aenl_identify_source_t;

/** Source over columns in memory (no copy; the arrays must outlive the source). */
typedef struct aenl_identify_arrays
{
    const double *const *cols;
    size_t n_cols, n_rows, row;
} aenl_identify_arrays_t;

/** Source over a CSV file: every column but the first (time). */
typedef struct aenl_identify_csv
{
    const char *path;
    void *csv;     /**< aenl_csv_t while open */
    size_t n_cols; /**< channels */
    char **names;  /**< n_cols channel names */
    size_t *col;   /**< file column of each channel */
    double *row;   /**< one file row */
} aenl_identify_csv_t;

/** Options. */
typedef struct aenl_identify_opts
{
    double bandwidth; /**< > 0: given (channel units, every channel); 0: cross-validation */
    int prefilter;    /**< 1 (default): low-pass at 8 / period; 0 off */
    size_t cv_max;    /**< samples of the bandwidth block (default 20000) */
    long channel;     /**< -1 all channels (default), else the index of the only one read */
    int forced;       /**< 1: the motion is forced, so a sustained oscillation is not taken for a
                           limit cycle (default 0) */
} aenl_identify_opts_t;

/** Paper-style display curves of one channel: lags 1, 10, 30 (clipped to the record). */
#define AENL_IDENTIFY_DISPLAY_LAGS 3
/** Most diagnoses aenl_identify_model_test runs: the first effect, a second on top of it, and two
 *  backfitting passes of two refits each. */
#define AENL_IDENTIFY_MAX_DIAGNOSES 6

/** Result for one channel. */
typedef struct aenl_identify_channel
{
    const char *name;
    aenl_classifier_result_t res;     /**< the host verdict: class, switching points, confidence */
    aenl_classifier_result_t onboard; /**< the core classifier on this channel's moments alone
                                           (what a data-acquisition unit computes) */
    aenl_rfs_fit_t rfs;  /**< the multi-channel restoring-force regression behind res */
    double evidence;     /**< the regression's t when it decided, else the core classifier's
                              (BIC linear - min BIC nonlinear) / independent points; 0 linear */
    double bandwidth;    /**< kernel half-width used, channel units */
    int bw_method;       /**< AENL_BW_CV, AENL_BW_RULE or -1 given */
    double period;       /**< dominant period, samples (0 when none was found) */
    double sustained;    /**< autocorrelation at 10 periods (near 1: a limit cycle; 0 none) */
    double kurtosis;     /**< of the pre-filtered signal: 1.5 a sinusoid, 3 a Gaussian process */
    long explained_by;   /**< channel whose law explains the law the regression found here (an
                              echo through the coupling; this channel is then linear), or -1 */
    double prefilter;    /**< cutoff as a fraction of the sample rate (0 none) */
    double noise_std;    /**< white-noise level estimated from differences, channel units */
    double dither_std;   /**< white noise the restoring-force regression added to reach its
                              noise floor (0.1 of the standard deviation), channel units (0:
                              none) */
    double x_min, x_max; /**< grid ends */
    uint16_t n_grid, n_lags;
    uint16_t lags[AENL_MOMENTS_MAX_LAGS];
    size_t n_samples, n_missing;
    /** Display curves [dir 0 all, 1 rising, 2 falling][lag][node]; NaN where empty. */
    uint16_t display_lags[AENL_IDENTIFY_DISPLAY_LAGS];
    uint16_t n_display;
    double *x;                /**< n_grid nodes */
    double *mean, *var;       /**< [3][n_display][n_grid] */
    double *position, *accel; /**< restoring-force points [3][n_grid] (lag expansion) */
} aenl_identify_channel_t;

/** The model-based test of `aenl identify --model` (aenl_identify_apply_model). */
typedef struct aenl_identify_model
{
    int applied;                    /**< 1: a diagnosis against a baseline model was applied */
    int explained;                  /**< 0: the baseline misses the record, but no candidate effect
                                         explains it */
    aenl_diagnose_effect_t effect;  /**< the effect named (NONE: the baseline fits) */
    aenl_sim_dof_t dof;             /**< its DOF */
    double gap_before, gap_after;   /**< the diagnosis' total gaps */
    aenl_diagnose_effect_t effect2; /**< a second effect, on another DOF (NONE: none found) */
    aenl_sim_dof_t dof2;            /**< its DOF */
    double gap_after2;              /**< total gap with both effects, each refitted with the
                                         other in place (NaN: no second effect) */
    int base_test;                  /**< the baseline fits within twice its floor: its summaries'
                                         test (aenl_diagnose_summary_test) -1 not run, 0 rejects
                                         it (the record's verdict stands), 1 accepts it (linear) */
    aenl_diagnose_sumtest_t base_sum; /**<   that test (base_test >= 0) */
    unsigned n_diagnoses;             /**< diagnoses run by aenl_identify_model_test (1..6) */
    long data_verdict;                /**< the record alone: channel named (-1 none), */
    aenl_class_t data_class;          /**<   class */
    double data_confidence;           /**<   and confidence */
} aenl_identify_model_t;

/** Result of one record. */
typedef struct aenl_identify_result
{
    size_t n_channels;
    aenl_identify_channel_t *ch;
    long verdict; /**< index of the channel named, -1 none (all linear or insufficient) */
    aenl_class_t verdict_class;
    double verdict_share;      /**< the named channel's share of what named it: its evidence
                                    among the nonlinear channels', or, named by the limit-cycle
                                    rule, its polynomial weight among the linear channels'
                                    (1 when it is the only one; 0 when none is named) */
    double verdict_confidence; /**< the named channel's confidence times verdict_share (on a
                                    limit cycle 1/3, each nonlinear class as likely, times
                                    verdict_share: one orbit does not tell the laws apart); with
                                    none named, the smallest of the decided channels' (linear),
                                    0 when no channel was decided */
    int decay_train;           /**< the motion decays between the impulses (aenl_impulse.h) */
    size_t impulses;           /**< impulsive events left out of the regression (aenl_impulse.h) */
    size_t impulse_rows;       /**< rows they took out */
    long limit_cycle; /**< channel whose sustained, constant-amplitude oscillation shows the
                           motion is a limit cycle (-1 none; set where the regression did not
                           decide) */
    aenl_identify_model_t model; /**< set by aenl_identify_apply_model (applied 0 otherwise) */
} aenl_identify_result_t;

void aenl_identify_opts_default(aenl_identify_opts_t *o);

/** Sources. aenl_identify_csv_source opens the file once to read the header (err set, E_IO/E_ARG
 *  on failure; E_ARG when time_column is given and no column has that name); the time column is
 *  the one named time_column, or (NULL) one aenl_csv_is_time_name knows; release with
 *  aenl_identify_csv_free. */
void aenl_identify_arrays_source(aenl_identify_source_t *src, aenl_identify_arrays_t *ctx,
                                 const double *const *cols, const char *const *names, size_t n_cols,
                                 size_t n_rows);
aenl_status_t aenl_identify_csv_source(aenl_identify_source_t *src, aenl_identify_csv_t *ctx,
                                       const char *path, const char *time_column, aenl_err_t *err);
void aenl_identify_csv_free(aenl_identify_csv_t *ctx);

/**
 * @brief Identify every channel (or opts->channel) of a record.
 * @return AENL_OK; AENL_E_ARG with a message for an unusable channel (no finite sample, constant,
 *         too short for the lags); errors of the source; AENL_E_IO out of memory. On error *out
 *         holds nothing to free.
 */
aenl_status_t aenl_identify_run(const aenl_identify_source_t *src, const aenl_identify_opts_t *opts,
                                aenl_identify_result_t *out, aenl_err_t *err);

void aenl_identify_free(aenl_identify_result_t *r);

/** The class with a polynomial's hardening or softening: "polynomial (hardening)". */
const char *aenl_identify_class_label(const aenl_classifier_result_t *res);
/**
 * @brief r as the JSON object of docs/identify.md (schema "aenl-identify/2") on out.
 * @param path  the record's file name, as given; rows its data rows.
 * @param model the baseline INI of a model-based test (NULL: none).
 * @return AENL_OK, or AENL_E_DIM when out of memory (nothing written).
 */
aenl_status_t aenl_identify_print_json(FILE *out, const aenl_identify_result_t *r, const char *path,
                                       size_t rows, const char *model);
/**
 * @brief r as a table on out: one line per channel, the notes, the model-based test's lines
 *        (when applied) and the verdict; o the options of the run (bandwidth, pre-filter).
 */
void aenl_identify_print_table(FILE *out, const aenl_identify_result_t *r, const char *path,
                               size_t rows, const aenl_identify_opts_t *o, const char *model);

/**
 * @brief Put the verdict of a model-based test in place of the record's own: a diagnosis of the
 *        same record against a baseline model (aenl_diagnose_run), read in identify's classes.
 *        Freeplay, hysteresis and the polynomial (hardening from its cubic's sign) keep their
 *        class; a preload (a constant moment: the stiffness keeps its slope) is linear. When the
 *        baseline fits within twice its noise floor, the record is linear if the summaries' test
 *        of the baseline also accepts it (p above AENL_DIAGNOSE_SUMTEST_LEVEL); if that test
 *        rejects it or did not run (no evidence either way: a small law under turbulence stays
 *        within the floor), and when the diagnosis finds a disagreement no candidate explains,
 *        the record's own verdict stands. The
 * named DOF's channel (by name) takes the fitted law: class, switching points (freeplay [α_f, α_f +
 * δ]; hysteresis the distinct kinks ±α_f, ±(α_f + δ) of both branches) with standard errors from
 * the summary fit (α_f + δ: sd(α_f) + sd(δ), a bound whatever their correlation; NaN without it).
 * Confidences are the weights exp(-score / 2) of the diagnosis' penalised gaps, (gap / floor)^2 +
 * penalty x parameters, the baseline's gap without penalty: the channel's is its class' share among
 *        its DOF's candidates and the baseline, the verdict's its share among all. Other
 *        channels keep the record's own analysis; the record's verdict is kept in res->model.
 * @return AENL_OK; AENL_E_ARG (err set, res unchanged) when the named DOF's channel is not among
 *         res's channels.
 */
aenl_status_t aenl_identify_apply_model(aenl_identify_result_t *res,
                                        const aenl_diagnose_result_t *d, aenl_err_t *err);

/**
 * @brief The model-based test of `aenl identify --model`: diagnose `record` (time column and the
 *        model's channels by name, aenl_diagnose_run) against the baseline `base` under `run`
 *        with the default options, then aenl_identify_apply_model(). When that names a law, a
 *        second diagnosis against the baseline with it looks for a second effect on the DOFs it
 *        left linear (forward selection, by the diagnosis' own rules: a disagreement beyond
 *        twice the noise floor that a candidate cuts by 30 %). If one is named, one backfitting
 *        pass refits the first DOF's law with the second's in the model, then the second's with
 *        the first's final law. The second effect stands only if that last diagnosis names it
 *        again; then its DOF's channel takes its law (res->model.effect2, dof2, gap_after2) and
 *        the verdict stays the first's. Minutes on long records.
 * @return AENL_OK; the errors of aenl_diagnose_run (AENL_E_ARG a record or model it cannot use,
 *         AENL_E_DIM a capacity) and of aenl_identify_apply_model; res unchanged on error.
 * @note time_column names the record's time column (NULL: one aenl_csv_is_time_name knows);
 *       progress (NULL: nobody) hears each diagnosis' stages (aenl_diagnose_opts_t.progress),
 *       from the start again for every diagnosis.
 */
aenl_status_t aenl_identify_model_test(aenl_identify_result_t *res, const aenl_table_t *record,
                                       const aenl_sim_model_t *base, const aenl_sim_run_t *run,
                                       const char *time_column, const aenl_progress_t *progress,
                                       aenl_err_t *err);

/** The record the figures are drawn from, as plain data besides the source that reads it. */
typedef struct aenl_identify_plot_record
{
    const char *path;   /**< the record's file: titles carry its base name, figures its stem */
    size_t n_rows;      /**< rows of a complete pass of the source */
    double dt;          /**< the time column's step; 0 without one (accelerations per sample^2) */
    const char *t_name; /**< the time axis' label (NULL: "row") */
    double (*row_time)(const void *ctx); /**< time of the row the source read last */
    const void *time_ctx;                /**< passed to row_time */
} aenl_identify_plot_record_t;

/**
 * @brief r's figures as PNG files in `dir` (which exists), drawn by gnuplot (aenl_plot_run); for
 *        each channel DIR/<stem>_<channel>_timeseries.png (the whole record as a min/max envelope
 *        over at most 1500 bins, and its last 12 dominant periods, 400 to 4000 rows, at full
 *        rate), _moments.png (the conditional mean and variance at the display lags) and
 *        _restoring.png (the restoring-force points, all and by direction), each with the
 *        switching points marked. <stem> is the record's file name without folder and extension.
 *        The time series is read again from `src` (one more pass, memory bounded by the bins and
 *        the rows shown), its time from rec->row_time, so a record of any length can be drawn.
 * @param done  called with each figure written (done_ctx passed on), so that the caller can list
 *              it and remove it on a later failure.
 * @return AENL_OK; else the first failure (the source's, gnuplot's, a temporary file's, done's,
 *         memory) with err set; the figures written before it stay (done has been told of them).
 */
aenl_status_t aenl_identify_plot(const aenl_identify_result_t *r, const aenl_identify_source_t *src,
                                 const aenl_identify_plot_record_t *rec, const char *dir,
                                 aenl_plot_done_fn done, void *done_ctx, aenl_err_t *err);

#endif /* AENL_TOOLS_IDENTIFY_H */
