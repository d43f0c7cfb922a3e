/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_em.h
 * @brief Host-only: EM identification of a switching (piecewise-affine) linear state-space model
 *        with the mode sequence fixed by thresholds (the seed paper's equations (13)-(14);
 *        docs/fit.md), and its export to the core switching Kalman filter.
 *
 * Model, samples k = 0 .. n-1 (y_k row k of an n x n_z row-major array, NaN = missing):
 *
 *     x_0 ~ N(x0, P0),   x_k = A_s x_{k-1} + b_s + v_k,  v_k ~ N(0, Q_s),  s = s_k
 *     y_k = C x_k + w_k, w_k ~ N(0, R)
 *
 * The mode s_k of the transition k-1 -> k is the number of thresholds t_i with
 * u_{k-1} >= t_i, where u is the switching output channel (the same rule as aenl_skf_mode_of). u is
 * the smoothed output C x_{k|n} of the least-squares initial model (so measurement noise does not
 * flip modes near a threshold), or the raw channel with opts.modes_from_data. The sequence is then
 * fixed: each EM iteration is an exact E-step (Kalman filter + Rauch-Tung-Striebel smoother with
 * lag-one covariances) and an exact M-step (closed form per mode, LAPACKE dposv), so the
 * log-likelihood never decreases (Shumway & Stoffer 1982, with an affine term per mode).
 *
 * Acceleration: plain EM converges linearly at the rate of the fraction of missing information,
 * which is close to one when the process noise is nearly rank-deficient (an airfoil driven by a
 * single gust input): the smoothed states along the undriven directions follow the current A and
 * the M-step hardly moves it. By default the iterations are SQUAREM (Varadhan & Roland 2008,
 * scheme S3): two EM steps are extrapolated, the extrapolated point is kept only if its
 * covariances are valid and its log-likelihood is not below that of the second step's start
 * (else the step length backs off to a plain EM step), then one EM step stabilises it. Every
 * logged value is the log-likelihood of an accepted parameter set and the log never decreases;
 * a rejected extrapolation costs one forward pass. opts.plain_em gives plain EM.
 *
 * Speed: the covariance side of the E-step (filter covariance, gain, smoother gain, smoothed and
 * lag-one covariances) depends only on the mode sequence and the missing-sample pattern, not on
 * the data values. It is computed with register-blocked small-matrix kernels, symmetric products
 * halved, one Cholesky factorisation per predicted covariance and no per-step allocation; inside
 * a run of constant mode it is frozen once it has converged (opts.steady_tol), which leaves only
 * the O(n_x^2) mean updates per step. The result equals the full recursion to about steady_tol.
 *
 * Initialisation by least squares (opts.init = AENL_EM_INIT_ARX, the default): the state is the
 * delay embedding x_k = (y_k, y_{k-1}, ...) truncated to n_x entries (so C = [I 0] and the
 * switching state is the switching channel); per mode, y_{k+1} is regressed on (x_k, 1); the
 * other rows shift. C stays [I 0] unless freed. By default the regression uses instrumental
 * variables (the same embedding p = ceil(n_x/n_z) samples earlier), which removes the
 * errors-in-variables bias of measurement noise. With AENL_EM_INIT_SUBSPACE the state is instead
 * the projection of the future outputs onto the past ones (covariance-driven stochastic subspace
 * identification, opts.ssi_rows block rows, in the basis where C = [I 0]) and the per-mode
 * regression is of x_{k+1} on (x_k, 1); it reads the dynamics from the output covariances at
 * lags >= 1, which white measurement noise does not touch. Both are starts: EM does the rest,
 * and on a flat likelihood different starts can end at different local maxima.
 *
 * Continuous-time reading of a discrete mode (aenl_em_modal): for each eigenvalue λ of A_s
 * (LAPACKE dgeev), s = ln(λ)/dt (principal branch), frequency f = |Im s|/(2π) in cycles per unit
 * of the data's time column (Hz when t is in seconds, per τ for the airfoil's nondimensional time),
 * damping ratio ζ = -Re s/|s|. Only pairs with Im λ > 0 are "oscillatory".
 *
 * Memory: results own heap arrays released by the matching _free. Errors: a status plus an
 * aenl_err_t message; nothing prints.
 */
#ifndef AENL_TOOLS_EM_H
#define AENL_TOOLS_EM_H

#include <stddef.h>

#include "aenl/aenl_skf.h"
#include "aenl_tools/aenl_io.h"
#include "aenl_tools/aenl_progress.h"
#include "aenl_tools/aenl_rng.h"

#define AENL_EM_MAX_MODES 8  /**< modes (thresholds + 1) */
#define AENL_EM_MAX_X     32 /**< states */
#define AENL_EM_MAX_U     8  /**< known inputs */

/** Default opts.steady_tol: relative tolerance of the steady-state covariance reuse. */
#define AENL_EM_STEADY_TOL 1e-10

/** Freeze flags (opts.freeze): these parameters keep their initial values. */
#define AENL_EM_FREEZE_A  0x01u
#define AENL_EM_FREEZE_B  0x02u
#define AENL_EM_FREEZE_Q  0x04u
#define AENL_EM_FREEZE_C  0x08u
#define AENL_EM_FREEZE_R  0x10u
#define AENL_EM_FREEZE_X0 0x20u

/** Starting model (opts.init). */
#define AENL_EM_INIT_ARX      0 /**< delay-embedding regression (IV unless opts.no_iv) */
#define AENL_EM_INIT_SUBSPACE 1 /**< covariance-driven stochastic subspace, then regression */

/** A switching model in double. Arrays are row-major and owned by the model. */
typedef struct aenl_em_model
{
    size_t n_x, n_z, n_modes;
    size_t switch_channel; /**< output channel the thresholds read (= state index with C = [I 0]) */
    double thresholds[AENL_EM_MAX_MODES]; /**< n_modes-1 ascending */
    double dt;                            /**< sample step (time unit of the data) */
    double *A;                            /**< n_modes * n_x * n_x */
    double *b;                            /**< n_modes * n_x */
    size_t n_u;                           /**< known inputs (0: none) */
    double *B;                            /**< n_modes * n_x * n_u: x_k += B u_{k-1} */
    double *Q;                            /**< n_modes * n_x * n_x */
    double *C;                            /**< n_z * n_x */
    double *R;                            /**< n_z * n_z */
    double *x0;                           /**< n_x */
    double *P0;                           /**< n_x * n_x */
} aenl_em_model_t;

/** Options (aenl_em_opts_default gives the defaults). */
typedef struct aenl_em_opts
{
    size_t n_states;                      /**< n_x >= n_z (default 0: 4 n_z) */
    size_t switch_channel;                /**< channel the thresholds read (default 0) */
    size_t n_thresholds;                  /**< 0 .. AENL_EM_MAX_MODES-1 */
    double thresholds[AENL_EM_MAX_MODES]; /**< ascending */
    double dt;                            /**< sample step; > 0 */
    size_t max_iter;                      /**< EM iterations (default 50) */
    double tol;          /**< stop when the log-likelihood gains less than tol*|ll| (0: never) */
    unsigned freeze;     /**< AENL_EM_FREEZE_* flags (default AENL_EM_FREEZE_C) */
    int modes_from_data; /**< 1: modes from the raw channel (default 0: smoothed) */
    int refine;          /**< 1: refine the thresholds by likelihood (coordinate search) */
    double refine_step;  /**< first search step (0: 10 % of the channel's std) */
    size_t refine_iter;  /**< EM iterations per candidate (default 5) */
    int no_iv;           /**< 1: plain least-squares start (default 0: instrumental variables) */
    int plain_em;        /**< 1: plain EM iterations (default 0: SQUAREM-accelerated EM) */
    int init;            /**< AENL_EM_INIT_* (default AENL_EM_INIT_ARX) */
    size_t ssi_rows;     /**< subspace start: block rows i (default 0: 4 (n_x / n_z + 2)) */
    const double *u;     /**< known inputs, n x n_u row-major, finite (NULL: none): u_k drives
                              the transition k -> k+1, x_{k+1} = A x_k + B u_k + b + w_k. B is
                              estimated with A and b (so A and b must not be frozen); the start
                              is the delay-embedding regression with the inputs' lags */
    size_t n_u;          /**< inputs in u (at most AENL_EM_MAX_U) */
    double steady_tol;   /**< steady-state covariance reuse: inside a run of constant mode, once
                              the filter (and smoother) covariance has converged to this relative
                              tolerance, the remaining steps reuse it instead of recomputing it
                              (default AENL_EM_STEADY_TOL; 0: the full recursion at every step) */
    const unsigned char *jump; /**< n flags or NULL: jump[k] != 0 when the transition k-1 -> k
                              carries a state jump (an impulse) beyond the process noise. Its
                              prediction covariance gains P_jump, and it is left out of the
                              M-step's transition statistics (A, b, B, Q): the jump is a free
                              parameter of its own, so it tells nothing about them */
    const double *P_jump;      /**< n_x x n_x, positive semi-definite (required with jump) */
} aenl_em_opts_t;

/** Result of aenl_em_fit. */
typedef struct aenl_em_result
{
    aenl_em_model_t model;
    size_t n_iter;       /**< log-likelihood values in loglik */
    double *loglik;      /**< one per iteration: the log-likelihood of the parameters entering
                              that iteration's E-step (non-decreasing) */
    double loglik_final; /**< of the returned model */
    size_t mode_count[AENL_EM_MAX_MODES]; /**< transitions assigned to each mode */
    size_t n_missing;   /**< samples with a NaN component (treated as fully missing) */
    size_t n_cov_steps; /**< filter steps whose covariance the last E-step computed (the other
                             n - n_cov_steps reused a converged steady state; n with
                             steady_tol = 0) */
} aenl_em_result_t;

/** One eigenvalue of a mode and its continuous-time reading. */
typedef struct aenl_em_eig
{
    double re, im;     /**< discrete eigenvalue λ */
    double s_re, s_im; /**< s = ln(λ)/dt */
    double frequency;  /**< |Im s|/(2π), cycles per time unit */
    double damping;    /**< -Re s/|s| (1 for a real positive λ with s < 0) */
} aenl_em_eig_t;

void aenl_em_opts_default(aenl_em_opts_t *opts);

/** Allocate a model (all zero). */
aenl_status_t aenl_em_model_alloc(aenl_em_model_t *m, size_t n_x, size_t n_z, size_t n_modes,
                                  aenl_err_t *err);
/** Release and zero; safe on a zeroed model. */
void aenl_em_model_free(aenl_em_model_t *m);
/** Deep copy into a fresh model. */
aenl_status_t aenl_em_model_copy(aenl_em_model_t *dst, const aenl_em_model_t *src, aenl_err_t *err);

/** Give an allocated model n_u known inputs (B zero; at most AENL_EM_MAX_U). The INI and C-header
 *  writers, aenl_em_loglik, aenl_em_simulate and aenl_em_to_skf refuse a model with inputs. */
aenl_status_t aenl_em_model_set_inputs(aenl_em_model_t *m, size_t n_u, aenl_err_t *err);

/**
 * @brief Identify the model from y (n x n_z row-major, NaN = missing sample).
 * @return AENL_OK; AENL_E_ARG bad options or too little data per mode (message says which);
 *         AENL_E_NOT_PD a singular regression; AENL_E_NUMERIC a non-finite likelihood.
 * @note O(max_iter · n · n_x^3) time, O(n · n_x^2) memory.
 */
aenl_status_t aenl_em_fit(const double *y, size_t n, size_t n_z, const aenl_em_opts_t *opts,
                          aenl_em_result_t *res, aenl_err_t *err);

/**
 * @brief Continue EM from a given model (its thresholds on the raw switching channel of y):
 *        opts->max_iter iterations (opts->freeze and tol apply). loglik (may be NULL) needs
 *        max_iter + 1 entries: one per iteration, then that of the returned model.
 */
aenl_status_t aenl_em_iterate(aenl_em_model_t *m, const double *y, size_t n,
                              const aenl_em_opts_t *opts, double *loglik, size_t *n_iter,
                              aenl_err_t *err);

/** Release a result and zero it. Safe on a zeroed result. */
void aenl_em_result_free(aenl_em_result_t *res);

/**
 * @brief Log-likelihood of y under a model, modes fixed by the thresholds on `u` (n values: the
 *        switching signal; NULL: the raw switching channel of y).
 */
aenl_status_t aenl_em_loglik(const aenl_em_model_t *m, const double *y, size_t n, const double *u,
                             double *ll, aenl_err_t *err);

/**
 * @brief Eigenvalues of mode `mode` (dgeev) and their continuous reading, sorted: oscillatory
 *        pairs (Im λ > 0, one entry each) by frequency first, then the real eigenvalues.
 *        eig needs n_x entries; *n_osc receives the number of oscillatory pairs.
 */
aenl_status_t aenl_em_modal(const aenl_em_model_t *m, size_t mode, aenl_em_eig_t *eig,
                            size_t *n_eig, size_t *n_osc, aenl_err_t *err);

/**
 * @brief The Cramer-Rao floor of one oscillatory mode: the relative standard deviations *sf of
 *        its frequency and *sz of its damping ratio that no unbiased estimate from n transitions
 *        at step dt beats, in the most favourable case (the mode alone, driven by white noise,
 *        observed without noise). f in cycles per time unit of dt, 0 < zeta < 1.
 * @return 1, or 0 (nothing written) when the floor is not defined: zeta outside (0, 1), f or dt
 *         not positive, f at or above the Nyquist frequency, fewer than 3 transitions.
 * @note A record's own noise, other modes and a split between modes make the real spread larger:
 *       the floor says how far a 2 % goal is from what the data can hold.
 */
int aenl_em_mode_floor(double f, double zeta, double dt, double n, double *sf, double *sz);

/**
 * @brief Noise-free simulation of the identified model from x_init (NULL: m->x0): y = C x,
 *        n samples into y_out (n x n_z), modes from the thresholds on (C x)[switch_channel].
 */
aenl_status_t aenl_em_simulate(const aenl_em_model_t *m, const double *x_init, size_t n,
                               double *y_out, aenl_err_t *err);

/**
 * @brief Simulation of the identified model with its noise, as the model says a record is made:
 *        x_0 ~ N(x0, P0) (x_init, when given, without noise), x_{k+1} = A_s x_k + b_s + w_k with
 *        w_k ~ N(0, Q_s), y_k = C x_k + v_k with v_k ~ N(0, R), the mode s from the thresholds on
 *        the noise-free output (C x_k)[switch_channel]. Draws from rng; rng NULL is
 *        aenl_em_simulate.
 * @return AENL_OK; AENL_E_NUMERIC when a covariance has no square root or the state diverges.
 */
aenl_status_t aenl_em_simulate_noisy(const aenl_em_model_t *m, const double *x_init, size_t n,
                                     aenl_rng_t *rng, double *y_out, aenl_err_t *err);

/** The spread of a fit's modal estimates by a parametric bootstrap (aenl_em_bootstrap): per mode
 *  s and oscillatory pair i of the fitted model (in aenl_em_modal's order). */
typedef struct aenl_em_boot
{
    size_t n_requested;                                  /**< replicates asked for */
    size_t n_ok;                                         /**< replicates whose refit succeeded */
    size_t n_pairs[AENL_EM_MAX_MODES];                   /**< oscillatory pairs of each mode */
    size_t found[AENL_EM_MAX_MODES][AENL_EM_MAX_X / 2];  /**< refits in which the pair is found */
    double f_sd[AENL_EM_MAX_MODES][AENL_EM_MAX_X / 2];   /**< frequency's standard error */
    double z_sd[AENL_EM_MAX_MODES][AENL_EM_MAX_X / 2];   /**< damping ratio's standard error */
    double f_bias[AENL_EM_MAX_MODES][AENL_EM_MAX_X / 2]; /**< median of the refits - the fit */
    double z_bias[AENL_EM_MAX_MODES][AENL_EM_MAX_X / 2];
} aenl_em_boot_t;

/**
 * @brief Standard errors and biases of the modal estimates by a parametric bootstrap: n_boot
 *        records of n samples simulated from the fitted model with its noise
 *        (aenl_em_simulate_noisy, seeded from seed), each fitted again with opts (the fit's own
 *        options) but the fitted thresholds held (no refinement). A pair of the fit and one of
 *        the refit match when each is the other's nearest in log frequency (found counts the
 *        refits with a match); the standard error is 1.4826 times the median absolute deviation
 *        of the matched values (robust to the rare refit that swaps two pairs), the bias their
 *        median less the fit's value; NaN for a pair found in fewer than 2 or in at most half of
 *        the refits. Costs n_boot fits; progress (may be NULL) hears after each.
 * @return AENL_OK (also when some refits fail: out->n_ok says how many succeeded); AENL_E_ARG
 *         bad arguments or a model with inputs; AENL_E_DIM out of memory.
 */
aenl_status_t aenl_em_bootstrap(const aenl_em_result_t *fit, const aenl_em_opts_t *opts, size_t n,
                                size_t n_boot, uint64_t seed, const aenl_progress_t *progress,
                                aenl_em_boot_t *out, aenl_err_t *err);

/**
 * @brief The core filter's model (threshold switching, no hysteresis band, dir from the change of
 *        the switching state). Fails with AENL_E_DIM when a size exceeds the core's capacities.
 */
aenl_status_t aenl_em_to_skf(const aenl_em_model_t *m, aenl_skf_model_t *out, aenl_err_t *err);

/** Write the model as an INI file ([model] sizes, dt, thresholds; [mode.N] A, b, Q; [output]). */
aenl_status_t aenl_em_write_ini(const aenl_em_model_t *m, const char *path, aenl_err_t *err);

/**
 * @brief Write a C header with a `static const aenl_skf_model_t <name>` initializer (float
 *        literals with 9 significant digits, `#error` when the core's capacities are too small).
 */
aenl_status_t aenl_em_write_c_header(const aenl_em_model_t *m, const char *name, const char *path,
                                     aenl_err_t *err);

#endif /* AENL_TOOLS_EM_H */
