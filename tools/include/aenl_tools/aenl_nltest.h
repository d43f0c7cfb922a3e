/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_nltest.h
 * @brief Host-only: identification from the record alone as one likelihood-based test.
 *
 * The record's linear part is a linear Gaussian state-space model fitted by maximum likelihood
 * (aenl_em, one mode): x_{t+1} = A x_t + b + w_t, y_t = C x_t + v_t, the measurement noise in
 * the measurement equation, its order chosen by BIC. Samples whose innovation is beyond what the
 * model's Gaussian noise allows (impulses: taps, kicks) restart the filter from a widened state
 * covariance. A channel whose fitted measurement noise is at the likelihood's boundary (a
 * noise-free record) is dithered with white noise of AENL_NLT_DITHER of its standard deviation
 * and the model fitted again, so that the innovations are noise, as the test assumes. Its Kalman
 * filter gives the innovations e_t, their covariances S_t and the filtered outputs u_t = C x_{t|t}.
 * A structural law in the degree of freedom seen by channel j enters as a force: x_{t+1} = ... + B
 * g(u_{j,t}, d_t), with B an unknown direction (one coefficient per state) and g a candidate shape;
 * d_t = sign(u_{j,t} - u_{j,t-1}) is the direction of motion that a hysteresis loop needs. g is a
 * function of the filtered past only, so under the linear model the innovations are independent of
 * it.
 *
 * Test (stage 1, one per channel). The heteroskedasticity-robust score test of B = 0 for the
 * generic shapes u^2, u^3, d and d u, with an offset and a perturbation of A along every filtered
 * state as nuisance (the first-order change of the fitted linear model): the shapes' columns
 * (the derivatives of the whitened innovations with respect to B) are partialled on the
 * nuisance columns, and the per-sample score contributions give a statistic that is chi-square
 * with 4 n_x degrees of freedom when the innovations are uncorrelated with the filtered past.
 * A channel is nonlinear when its p-value is below level / (number of channels) (Bonferroni);
 * the verdict's channel has the largest statistic among them.
 *
 * Law (stage 2, on the channels the test rejects). B is fixed to the direction that the generic
 * fit estimates (the leading singular vector of its coefficients), and every candidate law is
 * fitted on the same regression: polynomial (u^3, or u^3 and u^5), freeplay (a saturation
 * between two switching points: a gap in which the stiffness differs) and hysteresis (the gap
 * shifts with the direction of motion, mirrored about zero, plus a direction-dependent preload).
 * Switching points are profiled over a grid of quantiles of u and refined on a finer grid
 * around the best pair. The best law is the one of the smallest Bayesian information criterion
 * (the switching points counted as parameters); it is tested against each other law by Vuong's
 * test for non-nested models: the difference of their per-sample losses (the squared whitened
 * innovations each leaves), summed and less the penalty difference, over its long-run standard
 * deviation, standard normal when the two laws are equally close to the record. The law is
 * named when its confidence, 1 - 2 x the larger of the other laws' p-values, reaches
 * opts.min_confidence; else the class is undetermined and the candidates say which laws remain.
 * The verdict's channel is compared with the other rejecting channels' best laws the same way.
 * Each switching point comes with its profile-likelihood 95 % interval (the grid values whose
 * profile stays within chi2_1(0.95) = 3.84 of the best).
 *
 * Units: channels are scaled by their standard deviation inside; switching points are returned
 * in the channel's own unit. Errors: a status and an aenl_err_t message; nothing prints.
 */
#ifndef AENL_TOOLS_NLTEST_H
#define AENL_TOOLS_NLTEST_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "aenl/aenl_classifier.h"
#include "aenl_tools/aenl_io.h"
#include "aenl_tools/aenl_plot.h"
#include "aenl_tools/aenl_progress.h"

#define AENL_NLT_MAX_CH     8 /**< channels of a record */
#define AENL_NLT_MAX_POINTS 4 /**< switching points of one law */
#define AENL_NLT_MAX_INPUT  4 /**< known inputs (each drives the model with two values per step) */
/** Noise added to a channel whose fitted measurement noise is at the likelihood's boundary (its
 *  standard deviation below a tenth of this), in units of the channel's standard deviation: a
 *  noise-free record leaves the innovations a deterministic misfit, where the test is not valid */
#define AENL_NLT_DITHER 1e-3
/** Samples per period of the motion below which the output notes that the law's shape and
 *  switching points are resolved coarsely: the direction of motion between samples then lags
 *  the motion by more than 22.5 degrees of phase, and a cycle is seen at fewer positions */
#define AENL_NLT_MIN_SAMPLES_PER_PERIOD 8.0

/** Candidate laws, in the order of the weight arrays. */
typedef enum
{
    AENL_NLT_POLYNOMIAL = 0,
    AENL_NLT_FREEPLAY = 1,
    AENL_NLT_HYSTERESIS = 2,
    AENL_NLT_N_LAWS = 3
} aenl_nlt_law_t;

typedef struct aenl_nlt_opts
{
    double level;          /**< family-wise level of the test over the channels (default 0.01) */
    double min_confidence; /**< confidence a law needs to be named (default 0.9) */
    size_t n_states;       /**< states of the linear model (default 0: chosen by BIC among 4 and 6
                                per channel and 12, at most 12) */
    size_t em_iter;        /**< EM iterations of the linear fit (default 200) */
    const double *const *input; /**< known inputs (a measured force), n_input columns of the
                                     record's n samples (NULL: none): they drive the linear
                                     model with their values at both ends of a step (a
                                     first-order hold), x_{t+1} = A x_t + B0 u_t + B1 u_{t+1}
                                     + b, and are not tested */
    size_t n_input;             /**< at most AENL_NLT_MAX_INPUT */
    size_t n_controls;          /**< linear controls (default 0: none): records simulated from the
                                     fitted linear model, driven by the same inputs, with Gaussian
                                     noise of the fitted covariances, each tested like the record */
    uint64_t control_seed;      /**< their noise (default 1) */
    double *control_record;     /**< n x n_channels, row-major, or NULL (default): receives a
                                     linear control in the channels' units, the first of those
                                     above (noise seed control_seed), simulated whether or not
                                     n_controls asks for their tests */
    int impulsive;              /**< 1: the record is driven by impulses (taps, kicks, raps): the
                                     linear model is fitted again with them as state jumps, its
                                     noise estimated without their transitions, and tested so
                                     (default 0: Gaussian process noise throughout) */
    const aenl_progress_t *progress; /**< hears after each control (default NULL: nobody) */
} aenl_nlt_opts_t;

/** One channel: the test and, when it rejects, the laws. */
typedef struct aenl_nlt_channel
{
    double stat;                   /**< stage-1 chi-square statistic */
    double dof;                    /**< its degrees of freedom */
    double p;                      /**< its p-value */
    int nonlinear;                 /**< 1 when p < level / n_channels */
    aenl_class_t cls;              /**< LINEAR, POLYNOMIAL, FREEPLAY, HYSTERESIS, or INSUFFICIENT
                                        when undetermined (see undetermined) */
    int undetermined;              /**< 1: nonlinear, but no law reaches min_confidence */
    double gain[AENL_NLT_N_LAWS];  /**< chi-square gain of each law at its best switching
                                        points: its reduction of the squared innovations beyond
                                        the nuisance's, over the dispersion-scaled residual
                                        variance */
    double bic[AENL_NLT_N_LAWS];   /**< -gain + parameters ln(rows) */
    double law_p[AENL_NLT_N_LAWS]; /**< one-sided p-value of the test that the law is as close
                                        to the record as the law of the smallest bic (1 for
                                        that law) */
    double confidence;             /**< 1 - (laws - 1) x the largest other law_p, at least 0 */
    int hardening;                 /**< polynomial: 1 hardening, -1 softening, 0 unknown */
    size_t n_points;               /**< switching points of the named (or best) law */
    double points[AENL_NLT_MAX_POINTS];   /**< ascending, in the channel's unit */
    double point_lo[AENL_NLT_MAX_POINTS]; /**< profile-likelihood 95 % interval */
    double point_hi[AENL_NLT_MAX_POINTS];
    double samples_per_period; /**< of the channel's filtered motion: 2 pi / arccos of its
                                    lag-one autocorrelation (large for a slow or
                                    non-oscillating motion, infinite for a constant one);
                                    below AENL_NLT_MIN_SAMPLES_PER_PERIOD the law's shape is
                                    resolved coarsely */
    int dithered;              /**< 1: the channel's fitted measurement noise was at the
                                    boundary, and white noise of AENL_NLT_DITHER of its standard
                                    deviation was added */
    size_t control_exceed;     /**< linear controls whose statistic reaches this channel's */
    double control_p;          /**< (1 + control_exceed) / (1 + n_controls); 1 without controls */
    /** 1 when the laws were fitted (the channel rejects): aenl_nlt_law_force can draw them */
    int laws_fitted;
    /* Each law as fitted in the comparison, for aenl_nlt_law_force: coefficients and switching
     * points on the channel's standardised position, the channel's scale, the orientation. */
    double law_coef[AENL_NLT_N_LAWS][2];
    double law_pts[AENL_NLT_N_LAWS][2];
    double law_scale;
    int law_sign; /* the frequency's change with a force along the direction: -1, 0 (unknown), 1 */
} aenl_nlt_channel_t;

/** A (channel, law) model the record cannot reject against the best one. */
typedef struct aenl_nlt_candidate
{
    size_t channel;
    aenl_nlt_law_t law;
    double p; /**< one-sided p-value of the test that it is as close to the record as the best
                   (1 for the best) */
} aenl_nlt_candidate_t;

typedef struct aenl_nlt_result
{
    size_t n_channels, n_samples, n_states;
    size_t n_inputs;   /**< known inputs the linear model took */
    size_t n_impulses; /**< samples taken for impulses (the filter restarted there) */
    int jumps;         /**< 1: the impulses are state jumps of the linear model (opts.impulsive:
                            the model was fitted again without their transitions) */
    size_t n_dithered; /**< channels dithered (see ch[].dithered) */
    size_t n_controls; /**< linear controls tested (those that could not be fitted are left out) */
    size_t n_controls_nonlinear; /**< of those, the ones a channel rejects at the level: the
                                      test's false verdicts on linear records like this one */
    double loglik;               /**< of the linear model */
    double level;                /**< the level used */
    double rows;                 /**< regression rows (samples x channels) */
    aenl_nlt_channel_t ch[AENL_NLT_MAX_CH];
    long verdict; /**< channel of the best (channel, law) model among the rejecting channels,
                       or -1 */
    aenl_class_t verdict_class; /**< LINEAR when nothing rejects; INSUFFICIENT when
                                     undetermined or the record is too short */
    int undetermined;           /**< nonlinear, but the law is undetermined */
    double confidence;          /**< of the verdict, law and channel both right (Bonferroni):
                                     class_confidence + channel_confidence - 1, at least 0;
                                     1 - n_channels x the smallest stage-1 p for a linear
                                     verdict */
    double class_confidence;    /**< of the law: 1 - m x the largest p-value of a model with
                                     another law (m of them), at least 0; = confidence for a
                                     linear verdict */
    double channel_confidence;  /**< of the channel, the same over the models on other channels
                                     (1 when only one channel rejects) */
    size_t n_candidates;        /**< models still in play, the best first */
    aenl_nlt_candidate_t candidates[AENL_NLT_MAX_CH * AENL_NLT_N_LAWS];
} aenl_nlt_result_t;

void aenl_nlt_opts_default(aenl_nlt_opts_t *opts);

/**
 * @brief Test and identify a record: y is n x n_ch row-major, raw channel values, every one
 *        finite (the test takes complete rows only). res is valid only when AENL_OK returns.
 * @return AENL_OK; AENL_E_ARG for bad options, a missing sample, too few samples for the model
 *         (the message says how many it needs), a constant channel or one that barely moves;
 *         AENL_E_NUMERIC when the linear model cannot be fitted, or when linear controls or a
 *         control record are asked for and the fitted model is unstable (a pole on or outside
 *         the unit circle: a control simulated from it grows without bound); AENL_E_DIM out of
 *         memory.
 */
aenl_status_t aenl_nlt_run(const double *y, size_t n, size_t n_ch, const aenl_nlt_opts_t *opts,
                           aenl_nlt_result_t *res, aenl_err_t *err);

/** aenl_nlt_run on separate channel arrays: cols[j] holds the n samples of channel j. */
aenl_status_t aenl_nlt_run_columns(const double *const *cols, size_t n, size_t n_ch,
                                   const aenl_nlt_opts_t *opts, aenl_nlt_result_t *res,
                                   aenl_err_t *err);

/** Name of a law ("polynomial", "freeplay", "hysteresis"). */
const char *aenl_nlt_law_name(aenl_nlt_law_t law);

/**
 * @brief The force a fitted law adds at position u (the channel's units) moving in direction
 *        dir (+1 rising, -1 falling, 0 at rest), as the comparison fitted it at its best
 *        switching points: along the channel's force direction in the linear model's state,
 *        on one scale for the three laws (so their shapes and sizes compare), oriented so that
 *        a force that raises the oscillation's frequency grows with u (a hardening spring's
 *        shape). Its unit is the model's scaled state per sample: read the shape, not the
 *        value. NaN when c->laws_fitted is 0.
 */
double aenl_nlt_law_force(const aenl_nlt_channel_t *c, aenl_nlt_law_t law, double u, int dir);

/** The class a result names: "linear", "polynomial", "freeplay", "hysteresis", "undetermined"
 *  (nonlinear, no law named) or "insufficient". */
const char *aenl_nlt_class_name(aenl_class_t cls, int undetermined);

/**
 * @brief The result as one JSON object on `out` (schema aenl-identify-test/5): file,
 *        aenl_version, method "test", level, dt, model {states, samples, loglik, impulses},
 *        verdict {class, channel, switch_points, switch_point_lo, switch_point_hi, confidence,
 *        class_confidence, channel_confidence, candidates [{class, channel, p_value}]},
 *        channels [{name, class, statistic, dof, p_value, nonlinear, law_p_values {polynomial,
 *        freeplay, hysteresis}, confidence, samples_per_period and period_samples (the same;
 *        null when infinite), period_s, hardening, switch_points, switch_point_lo,
 *        switch_point_hi}], notes [the notes the table prints, lead_note first],
 *        model.inputs [names] when the model took known inputs, model.dithered [names] when some
 *        channels were dithered, and controls (their number) and controls_nonlinear (those a
 *        channel rejects) with each channel's control_exceed and control_p when linear controls
 *        were run. names: the
 *        channels; input_names: the inputs (NULL when there are none); dt: the record's sample
 *        step in its time column's unit, NaN (null in the JSON, and every period_s null) when
 *        it has none; lead_note: a note of the caller's (NULL: none).
 * @return AENL_OK, or AENL_E_DIM when memory runs out (nothing is written then).
 */
aenl_status_t aenl_nlt_print_json(FILE *out, const aenl_nlt_result_t *r, const char *const *names,
                                  const char *const *input_names, const char *path, double dt,
                                  const char *lead_note);

/** The result as a table on `out` (what the JSON holds, for a reader). */
void aenl_nlt_print_table(FILE *out, const aenl_nlt_result_t *r, const char *const *names,
                          const char *const *input_names, const char *path);

/**
 * @brief The result's figures as PNG files in `dir` (which exists), drawn by gnuplot
 *        (aenl_plot_run): for each of the nz tested channels, DIR/<stem>_<channel>_timeseries.png
 *        (the whole record as a min/max envelope, its last samples at full rate, the switching
 *        points marked) and, for a channel whose laws were fitted, DIR/<stem>_<channel>_law.png
 *        (each law less its least-squares line over the record, which leaves the part the law
 *        adds to the linear model's stiffness, the law of the smallest BIC named). <stem> is the
 *        record's file name without folder and extension.
 * @param res   the test's result on chan (aenl_nlt_run_columns).
 * @param rec   the record: its path, sample count and time column (NULL: the sample index).
 * @param chan  the nz tested channels (rec->n samples each), names their names.
 * @param done  called with each figure written (done_ctx passed on), so that the caller can list
 *              it and remove it on a later failure.
 * @return AENL_OK; else the first failure (gnuplot's, a temporary file's, done's) with err set;
 *         the figures written before it stay (done has been told of them).
 */
aenl_status_t aenl_nlt_plot(const aenl_nlt_result_t *res, const aenl_plot_record_t *rec,
                            const double *const *chan, const char *const *names, size_t nz,
                            const char *dir, aenl_plot_done_fn done, void *done_ctx,
                            aenl_err_t *err);

#endif /* AENL_TOOLS_NLTEST_H */
