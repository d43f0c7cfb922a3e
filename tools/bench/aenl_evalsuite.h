/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_evalsuite.h
 * @brief Host-only evaluation suite of identification cases, generated from seeds with the
 *        simulators: every case is a simulated record with its truth (class, channel,
 *        switching points, gap width), reproducible from (suite seed, index) and rerunnable with
 *        `aenl simulate` from the INI it can write.
 *
 * Strata. Case `index` belongs to slot `index mod 60` and SNR level `(index / 60 + slot) mod 4`
 * (SNR ∞, 10, 3, 2), so any 240 consecutive indices hold every (slot, SNR) pair exactly once.
 * A slot is (variant, model, nonlinear DOF, regime); the 60 slots are every physically possible
 * combination below, interleaved so that consecutive slots cycle through the variants (a short
 * run of the suite is still balanced), with the linear slots listed twice:
 *
 *  | variant     | decay, turbulence                  | limit cycle (LCO)                      |
 *  |-------------|------------------------------------|----------------------------------------|
 *  | linear      | airfoil2dof, section3dof (x2)      | none: a linear system has no LCO       |
 *  | hardening   | 2-DOF pitch, plunge; 3-DOF h, α, β | 2-DOF pitch, 3-DOF pitch               |
 *  | softening   | 2-DOF pitch, plunge; 3-DOF h, α, β | 2-DOF pitch, plunge; 3-DOF pitch, h    |
 *  | freeplay    | 2-DOF pitch, plunge; 3-DOF h, α, β | 2-DOF pitch, 3-DOF pitch, flap         |
 *  | hysteresis  | 2-DOF pitch, plunge; 3-DOF h, α, β | 2-DOF pitch, 3-DOF pitch, flap         |
 *
 * Why some LCOs are absent: a stable limit cycle needs the linearised flutter speed to rise with
 * the amplitude. With the describing-function stiffness N(A) of the law, the flutter speed
 * U_f(N) of these models rises with the pitch stiffness (2-DOF; 3-DOF above N ~ 0.2), falls with
 * the plunge stiffness (both models) and is flat in the flap stiffness above N ~ 0.5. So a
 * freeplay or hysteresis gap (N rising with A) gives stable LCOs in pitch and flap but only
 * unstable ones in plunge; a hardening cubic (N rising) gives them in pitch only (in the flap the
 * speed band, 23.9..24.1 m/s, is too narrow to be a real test condition); a softening law
 * (N falling, then rising through the quintic term) gives them in plunge (falling part) and pitch
 * (rising part), not in the flap (it would need N < 0.5, a snap-through spring).
 *
 * Laws (docs/simulate.md), drawn at unit amplitude and scaled to the case's amplitude A (DOF units;
 * decay and LCO: drawn log-uniform per DOF, pitch 1..6 deg, 3-DOF pitch 0.5..4 deg, flap 1..6 deg,
 * plunge ξ 0.02..0.2 or h 2..20 mm; turbulence: √2 x the rms of a linear pilot run, 8000 samples
 * at the drawn gust intensity 0.2..2 %):
 *  - hardening: R = x + βx³ with s = βA² in 0.6..1.5 (LCO), 2.5..6 (decay: the release
 *    amplitude) or 1..5 (turbulence);
 *  - softening: R = x − a x³ + c a² x⁵, c in 0.5..0.55, s = aA² in 1.4..3 (pitch LCO), 0.6..0.95
 *    (plunge LCO), 1.8..2.5 (decay), 0.4..1 (turbulence): the secant stiffness dips to 1 − 1/(4c)
 *    (tangent to 0.10..0.18) before the quintic term hardens it, so the force stays monotone
 *    (a pure softening cubic has a static divergence);
 *  - freeplay: gap δ = 2 r A, r = (δ/2)/A in 0.15..0.5 (LCO), 0.1..0.35 (decay), 0.3..0.8
 *    (turbulence); half the cases off-centre (α_f = 0 as in Lee's classic case, or the centre
 *    drawn in ±δ), a third with a preload M0 = ±(0.05..0.3)δ, a third with an inner stiffness
 *    M_f = 0.1..0.4 (always in 3-DOF pitch decay/turbulence: at M_f = 0 it diverges statically);
 *  - hysteresis: the odd-symmetric loop with α_f = 0 (half the cases: three kinks −δ, 0, δ) or
 *    α_f in 0.25..0.5 δ (four kinks at least δ/2 apart), (α_f + δ)/A as r above (LCO 0.2..0.6);
 *    preload M0 in 0..α_f + δ/4 (LCO: the outer loop injects energy), α_f + (0.5..0.75)δ (decay:
 *    a dissipative loop) or 0..α_f + δ/2 (turbulence).
 *
 * Velocity, from LAPACKE eigenvalues of aenl_sim_state_matrix with the nonlinear DOF at slope N:
 *  - LCO: N* = N(A) of the law about its centre (where the mean force over the cycle is zero);
 *    the velocity where the system linearised at N* turns unstable, accepted only if the cycle is
 *    stable there (N(1.15 A) stable, N(A/1.15) unstable); initial displacement centre + A; the
 *    sampling follows that neutral mode's frequency.
 *  - decay and turbulence: 50..95 % (decay) or 50..90 % (turbulence) of the lowest instability
 *    speed over the stiffnesses the law meets (N at amplitudes up to 1.25 A or 2 A, and slope 1),
 *    so every amplitude is stable: the motion is not a limit cycle. The sampling follows the
 *    oscillatory mode in which the nonlinear DOF (linear: the kicked DOF) has the largest share.
 * 2-DOF parameters vary around the classic case (μ 70..130, ω̄ 0.15..0.3, ζ_α, ζ_ξ 0..0.005); the
 * 3-DOF keeps Conner's. Velocities stay in U* 0.3..20 or 1.5..60 m/s. Sampling: 12..60 samples
 * per period of that mode (log-uniform), 20 000..60 000 samples; the first is the initial state.
 *
 * Regimes:
 *  - decay: a sequence of releases, like repeated stick raps: the simulator's kick train
 *    ([excitation] type = kicks, one run). Every release_samples samples, the first at t = 0,
 *    the rate of the DOF (linear cases: pitch 70 %, plunge 30 %) jumps by a kick of random sign
 *    whose size is uniform between the kicks with the energy of the law at amplitudes 0.8 A and
 *    1.25 A, scaled (1..4x) so that a pilot ring-down's first excursion reaches A; a release
 *    lasts until the pilot's excursion falls below A/F (F 3..10) and, for a gap law, below 2.5x
 *    the switching points' largest distance from the centre; at least 3 periods, at most 150.
 *    The state (aerodynamic states included) carries on through a kick, and the 2-DOF start-up
 *    terms are off (a release in established flow).
 *  - LCO: one run from the initial displacement (the transient included).
 *  - turbulence: the gust model of aenl_sim.h, length scale 2 semichords or 0.25 m.
 * Integration: rtol 1e-8 (1e-7 with turbulence, where the integrator restarts at every held gust
 * value), atol 1e-12.
 *
 * Truth must be material. After the noise-free run, an attempt is rejected and redrawn (a new
 * sub-seed) when: any sample is not finite, or the motion diverges (|x| beyond 20 A, or the last
 * tenth's rms over 3x the record's); the regime is not what was asked (decay: the median over the
 * releases of rms(last fifth) / rms(first fifth) not below 0.8; LCO: the last quarter's rms not
 * within 0.8..1.25 x the second quarter's, or its amplitude below 0.2 A; turbulence: the halves'
 * rms ratio outside 0.5..2); freeplay/hysteresis: fewer than 5 % of the samples below (lowest
 * switching point − δ/4) or above (highest + δ/4), or a gap δ under 6 % of the 1..99 % quantile
 * range; polynomial: the largest secant-stiffness change |R(x)/x − 1| over |x| <= √2 x_rms under
 * 0.4 (for the cubic this is |β| x_rms² >= 0.2). The design rejects too (no stable cycle, a
 * critical speed below the range, the simulator's own errors). Attempts are counted in the case.
 *
 * Noise: after the checks, exactly the simulator's measurement noise (aenl_sim_simulate with the
 * case's run: per channel std(clean)/snr, one generator seeded with noise_seed), so the written
 * INI reproduces every record bit for bit (a decay's releases are its kick train).
 *
 * Memory: a case owns its columns (heap, aenl_eval_case_free). No global state; re-entrant.
 */
#ifndef AENL_TOOLS_EVALSUITE_H
#define AENL_TOOLS_EVALSUITE_H

#include <stddef.h>
#include <stdint.h>

#include "aenl/aenl_classifier.h"
#include "aenl_tools/aenl_io.h"
#include "aenl_tools/aenl_sim.h"

#define AENL_EVAL_N_SLOTS     60u /**< (variant, model, DOF, regime) slots */
#define AENL_EVAL_N_SNR       4u  /**< SNR levels: ∞, 10, 3, 2 */
#define AENL_EVAL_MAX_ATTEMPT 16u /**< attempts per case before giving up (AENL_E_NUMERIC) */
#define AENL_EVAL_MAX_SWITCH  4u  /**< switching points at most (hysteresis) */
#define AENL_EVAL_REASONS_CAP 192 /**< bytes of a case's rejection reasons */

/** What the structure carries; the truth class follows (hardening/softening: polynomial). */
typedef enum aenl_eval_variant
{
    AENL_EVAL_LINEAR = 0,
    AENL_EVAL_HARDENING = 1,
    AENL_EVAL_SOFTENING = 2,
    AENL_EVAL_FREEPLAY = 3,
    AENL_EVAL_HYSTERESIS = 4
} aenl_eval_variant_t;
#define AENL_EVAL_N_VARIANTS 5u

typedef enum aenl_eval_regime
{
    AENL_EVAL_DECAY = 0,     /**< free decay from an initial displacement */
    AENL_EVAL_LCO = 1,       /**< limit-cycle oscillation */
    AENL_EVAL_TURBULENCE = 2 /**< stable system driven by the gust model */
} aenl_eval_regime_t;
#define AENL_EVAL_N_REGIMES 3u

/** The stratum of a case (independent of the suite seed). */
typedef struct aenl_eval_stratum
{
    aenl_eval_variant_t variant;
    aenl_sim_type_t model;
    int dof; /**< aenl_sim_dof_t of the nonlinear law; -1 for linear */
    aenl_eval_regime_t regime;
    double snr;         /**< 0 for no noise (∞), else 10, 3 or 2 */
    unsigned snr_level; /**< 0..3 for ∞, 10, 3, 2 */
} aenl_eval_stratum_t;

/** Materiality figures of the accepted run (noise-free nonlinear channel). */
typedef struct aenl_eval_metrics
{
    double frac_below;  /**< share of samples below the lowest switching point − δ/4 */
    double frac_above;  /**< share above the highest + δ/4 */
    double gap_ratio;   /**< δ / (99 % − 1 % quantile range) */
    double kappa;       /**< polynomial: largest |R(x)/x − 1| over |x| <= √2 x_rms */
    double x_rms;       /**< rms of the nonlinear channel about 0 (linear: first channel) */
    double trend_ratio; /**< decay: rms last/first fifth; LCO: last/second quarter; turbulence:
                             second/first half */
} aenl_eval_metrics_t;

/** One generated case. All fields are set by aenl_eval_case_make. */
typedef struct aenl_eval_case
{
    uint64_t suite_seed;
    size_t index;
    unsigned attempt; /**< accepted attempt (0 first); = rejections before it */
    char reject_reasons[AENL_EVAL_REASONS_CAP]; /**< the rejected attempts' reasons, "; "-separated
                                                     (cut when long) */
    aenl_eval_stratum_t stratum;

    /* truth */
    aenl_class_t cls;    /**< linear, polynomial, freeplay or hysteresis */
    int hardening;       /**< polynomial: +1 hardening, -1 softening; else 0 */
    const char *channel; /**< name of the nonlinear channel ("" for linear), static */
    long channel_index;  /**< its column in cols/names, -1 for linear */
    size_t n_switch;     /**< switching points (0 for linear and polynomial) */
    double switch_points[AENL_EVAL_MAX_SWITCH]; /**< ascending, channel units */
    double gap;                                 /**< δ (freeplay/hysteresis), else 0 */
    char description[320];

    /* how it was made */
    aenl_sim_model_t model;
    aenl_sim_run_t run;
    double amplitude;          /**< design amplitude A (DOF units) */
    double samples_per_period; /**< design value */
    double velocity_ratio;     /**< velocity / linear flutter speed (laws at slope 1) */
    aenl_eval_metrics_t metrics;

    size_t release_samples; /**< decay: samples per release (release i starts at i times it) */
    size_t n_releases;      /**< decay: releases in the record (else 0) */

    /* the record */
    size_t n_samples;
    size_t n_channels;     /**< 2 (alpha, xi) or 3 (h, alpha, beta) */
    const char *names[3];  /**< channel names (static strings) */
    const double *cols[3]; /**< noisy columns (views into y) */
    double *y;             /**< noisy data, channel c at y[c * n_samples] */
    double *clean;         /**< the noise-free run, same layout */
} aenl_eval_case_t;

/** @brief Stratum of case `index` (cheap: no simulation). */
void aenl_eval_stratum_of(size_t index, aenl_eval_stratum_t *s);

/** Lower-case names for tables: "linear", "hardening", ...; "decay", "lco", "turbulence". */
const char *aenl_eval_variant_name(aenl_eval_variant_t v);
const char *aenl_eval_regime_name(aenl_eval_regime_t r);
/** "pitch", "plunge", "flap", or "-" for dof < 0. */
const char *aenl_eval_dof_name(int dof);

/**
 * @brief Generate case `index` of the suite `suite_seed`: design, simulate, check materiality
 *        (redrawing up to AENL_EVAL_MAX_ATTEMPT times), add the noise.
 * @param[out] out  the case (free with aenl_eval_case_free); zeroed on failure
 * @return AENL_OK; AENL_E_ARG out NULL; AENL_E_IO out of memory; AENL_E_NUMERIC no attempt was
 *         accepted (message lists the reasons).
 * @note Typically 0.05..0.5 s per attempt: a few hundred 8x8/14x14 eigenproblems, pilot runs
 *       (turbulence: 8000 samples; decay: one or two ring-downs) and the run of 20k..60k samples.
 */
aenl_status_t aenl_eval_case_make(uint64_t suite_seed, size_t index, aenl_eval_case_t *out,
                                  aenl_err_t *err);

/** RK4 steps per output sample of aenl_eval_options_t's rk4. */
#define AENL_EVAL_RK4_STEPS 8

/** A simulator other than the suite's own, for a look at how identification carries over. */
typedef struct aenl_eval_options
{
    int rk4; /**< naive fixed-step RK4, AENL_EVAL_RK4_STEPS a sample (aenl_sim_simulate_rk4:
                  no event location; hysteresis switches on the rate's sign and
                  never sticks) instead of the event-located integrator */
    aenl_sim_gust_t spectrum; /**< gust spectrum of the turbulence records (first order: 0) */
} aenl_eval_options_t;

/**
 * @brief aenl_eval_case_make with another simulator (opt NULL: the suite's own). The design and
 *        truth are drawn the same way, every run of the design (pilots included) uses opt.
 */
aenl_status_t aenl_eval_case_make_with(uint64_t suite_seed, size_t index,
                                       const aenl_eval_options_t *opt, aenl_eval_case_t *out,
                                       aenl_err_t *err);

/**
 * @brief The design of one attempt without simulating: stratum, model, run and truth (the
 *        record fields stay empty). For checks of the truth against the law.
 * @return AENL_OK; AENL_E_NUMERIC when this attempt is rejected at the design step (message).
 */
aenl_status_t aenl_eval_case_design(uint64_t suite_seed, size_t index, unsigned attempt,
                                    aenl_eval_case_t *out, aenl_err_t *err);

/** @brief Release the columns and zero the case. Safe on a zeroed case. */
void aenl_eval_case_free(aenl_eval_case_t *c);

/**
 * @brief Write the case's model INI (docs/simulate.md; values in radians/SI with 17 digits, the
 *        case description and truth as comments): `aenl simulate` on it reproduces the noisy
 *        record exactly (a decay's releases are the run's kick train).
 * @return AENL_OK or AENL_E_IO with a message.
 */
aenl_status_t aenl_eval_case_write_ini(const aenl_eval_case_t *c, const char *path,
                                       aenl_err_t *err);

#endif /* AENL_TOOLS_EVALSUITE_H */
