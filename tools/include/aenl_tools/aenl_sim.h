/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sim.h
 * @brief Host-only aeroelastic simulators with structural nonlinearities, and linear flutter.
 *
 * Models (described with their INI keys in docs/simulate.md):
 *  - AENL_SIM_AIRFOIL2DOF: 2-DOF pitch-plunge airfoil, Wagner aerodynamics, 8 states (Lee, Price
 *    & Wong 1999), time τ = U t / b, velocity U* = U/(b ω_α); optional Lee start-up terms f(τ),
 *    g(τ) (on by default).
 *  - AENL_SIM_SECTION3DOF: 3-DOF typical section with trailing-edge flap (Conner, Tang, Dowell &
 *    Virgin 1997), Theodorsen T-functions with the R.T. Jones Wagner filter, Conner parameters as
 *    defaults, time in seconds, velocity in m/s.
 *
 * Restoring laws per DOF (pitch, plunge, flap): linear, polynomial, freeplay with preload and
 * inner stiffness, hysteresis with sticking (defined in docs/simulate.md, "Restoring laws"). Any
 * number of DOFs may be nonlinear at once.
 *
 * Integration: adaptive Dormand-Prince 5(4) with its 4th-order dense output
 * (Shampine's interpolant). On each branch ("mode") the right-hand side is smooth. After each
 * accepted step every switching function of the mode is checked at 4 points of the dense output
 * (so a dip across and back inside one step is still seen), the earliest crossing is located on
 * the interpolant (Illinois method), the step is cut there, the mode is changed and the
 * integration restarts. Safeguards: arming (a function sitting on its surface at a restart is
 * held at its "inside" sign for 1e-7 of an output step) and grazing (a boundary reached with a
 * negligible normal velocity is crossed or not according to the sign of the acceleration).
 * Hysteresis reversals are α' = 0 events; when neither direction is consistent the DOF sticks
 * (Filippov sliding: ẋ = ẍ = 0, restoring force = the value that holds it) until that value leaves
 * [M−(x), M+(x)]. Output is sampled on the uniform grid t_k = k dt from the dense output.
 *
 * Turbulence (optional broadband forcing, [excitation] type = turbulence): a vertical gust
 * velocity w_g, filtered white noise with time constant T = L/U, of one of two spectra
 * ([excitation] spectrum):
 *  - first_order (default): dw_g/dt = (−w_g + u(t)) / T, autocorrelation σ² exp(−|τ|/T);
 *  - dryden: the Dryden vertical-gust filter (1 + √3 T s)/(1 + T s)² as two lags in series,
 *    T z1' = −z1 + u, T z2' = −z2 + z1, w_g = √3 z1 + (1 − √3) z2; autocorrelation
 *    σ² (1 − |τ|/(2T)) exp(−|τ|/T): at the same variance half the first order's spectral
 *    density at low frequency and 1.5 times it at high frequency (both fall as ω⁻²).
 * u is white noise held constant over each output interval dt (a new Gaussian value per
 * interval from the seeded portable generator). The variance of u is chosen so that the sampled
 * gust has the exact stationary standard deviation std(w_g) = intensity · U (the stationary
 * covariance of the exactly discretised filter; first order: with e = exp(−dt/T),
 * var(u) = (intensity U)² (1 + e)/(1 − e)), and the filter starts in a draw from that stationary
 * distribution. The gust enters as a gust angle of attack w_g/U added
 * to the 3/4-chord downwash and passes through the same Wagner filter as the motion-induced
 * downwash (a simplification of the Küssner sharp-edged-gust function). L is `length_scale`:
 * semichords for airfoil2dof (default 2), metres for section3dof (default 0.25 m). The hold
 * instants are breakpoints of the integrator (it stops and restarts there), so the solution stays
 * exact for the piecewise-constant input. A run with intensity 0 equals a run without turbulence.
 *
 * Kicks (optional, [excitation] type = kicks): a train of releases in one record, like stick
 * raps or hammer taps on a rig. At t = 0 and every `every` after it the rate of one DOF jumps by
 * a size drawn uniformly from [rate, rate_max] with a random, alternating or positive sign, from
 * its own seeded generator; the integrator stops at each kick, applies it and restarts (a
 * hysteresis DOF takes the direction of its new rate). Displacements and the aerodynamic and
 * gust states carry on, so a release starts where the previous one has rung down to.
 *
 * Measurement noise ([noise] snr): for every output channel, independent Gaussian noise of
 * standard deviation std(clean channel)/snr is added after the clean run, from its own seed.
 *
 * Memory: results are heap arrays released by aenl_sim_result_free(). No global state; every
 * function is re-entrant.
 */
#ifndef AENL_TOOLS_SIM_H
#define AENL_TOOLS_SIM_H

#include <stddef.h>
#include <stdio.h>
#include <stdint.h>

#include "aenl_tools/aenl_io.h"

#define AENL_SIM_MAX_Q    3 /**< structural DOFs */
#define AENL_SIM_MAX_Z    8 /**< aerodynamic lag states (incl. gust filter states) */
#define AENL_SIM_MAX_X    (2 * AENL_SIM_MAX_Q + AENL_SIM_MAX_Z + 2)
#define AENL_SIM_MAX_POLY 9 /**< polynomial restoring law: up to x^9 */
#define AENL_SIM_N_DOF    3 /**< law slots: pitch, plunge, flap */

typedef enum aenl_sim_type
{
    AENL_SIM_AIRFOIL2DOF = 0, /**< 2-DOF pitch-plunge airfoil, time τ = U t / b */
    AENL_SIM_SECTION3DOF = 1  /**< 3-DOF section with trailing-edge flap, time in s */
} aenl_sim_type_t;

/** Law slots, as INI sections [pitch], [plunge], [flap]. */
typedef enum aenl_sim_dof
{
    AENL_SIM_DOF_PITCH = 0,
    AENL_SIM_DOF_PLUNGE = 1,
    AENL_SIM_DOF_FLAP = 2
} aenl_sim_dof_t;

typedef enum aenl_sim_law_kind
{
    AENL_SIM_LAW_LINEAR = 0,     /**< R(x) = x */
    AENL_SIM_LAW_POLYNOMIAL = 1, /**< R(x) = Σ_k coeffs[k-1] x^k */
    AENL_SIM_LAW_FREEPLAY = 2,   /**< Lee form with preload and inner stiffness */
    AENL_SIM_LAW_HYSTERESIS = 3  /**< odd-symmetric loop, with sticking */
} aenl_sim_law_kind_t;

/**
 * Restoring law of one DOF, in the DOF's own unit (rad for angles; ξ = h/b for the airfoil2dof
 * plunge; metres for the section3dof plunge). The force is κ·R(x) (κ the linear stiffness).
 */
typedef struct aenl_sim_law
{
    aenl_sim_law_kind_t kind;
    double delta;           /**< freeplay/hysteresis: full gap width δ >= 0 */
    double x_f;             /**< start of the gap α_f */
    double preload;         /**< M0 */
    double inner_stiffness; /**< M_f: slope inside the gap (0 in the usual hysteresis loop) */
    size_t n_coeffs;        /**< polynomial: number of coefficients, 1..AENL_SIM_MAX_POLY */
    double coeffs[AENL_SIM_MAX_POLY]; /**< coeffs[k-1] multiplies x^k */
} aenl_sim_law_t;

/** airfoil2dof parameters (the INI's [model] keys, docs/simulate.md). */
typedef struct aenl_sim_airfoil
{
    double mu, a_h, x_alpha, r_alpha, omega_bar, zeta_alpha, zeta_xi;
    double ustar;   /**< reduced velocity U* > 0 */
    int ic_forcing; /**< 1 (default): keep the Wagner integrals' start-up terms f(τ), g(τ) */
} aenl_sim_airfoil_t;

/** section3dof parameters (SI units per unit span; Conner's values by default). */
typedef struct aenl_sim_section
{
    double b, a, c, m, m_t, x_alpha, x_beta, r_alpha, r_beta;
    double omega_h, omega_alpha, omega_beta; /**< rad/s */
    double zeta_h, zeta_alpha, zeta_beta, rho;
    double velocity; /**< m/s > 0 */
} aenl_sim_section_t;

/** Whether `aenl diagnose` estimates a baseline's initial state from the record ([initial]
 *  estimate). It is a property of the test description, not of the physics: `aenl simulate`
 *  ignores it. */
typedef enum aenl_sim_initial
{
    AENL_SIM_INITIAL_AUTO = 0,     /**< not given: estimated on a run without turbulence or
                                        kicks when the state is zero (a baseline that would
                                        not move) */
    AENL_SIM_INITIAL_ESTIMATE = 1, /**< estimate = true: estimated on a run without turbulence,
                                        starting from the state given */
    AENL_SIM_INITIAL_GIVEN = 2     /**< estimate = false: the state as given */
} aenl_sim_initial_t;

/** A physical model: type, parameters, restoring laws and initial state. */
typedef struct aenl_sim_model
{
    aenl_sim_type_t type;
    aenl_sim_initial_t initial;         /**< [initial] estimate (aenl diagnose) */
    aenl_sim_airfoil_t airfoil;         /**< used when type == AENL_SIM_AIRFOIL2DOF */
    aenl_sim_section_t section;         /**< used when type == AENL_SIM_SECTION3DOF */
    aenl_sim_law_t law[AENL_SIM_N_DOF]; /**< indexed by aenl_sim_dof_t; flap unused for 2-DOF */
    double x0[AENL_SIM_N_DOF];          /**< initial displacement per DOF (rad, ξ or m) */
    double v0[AENL_SIM_N_DOF];          /**< initial velocity per DOF, per model time unit */
} aenl_sim_model_t;

/** Spectrum of the turbulence's gust velocity (see the file comment). */
typedef enum aenl_sim_gust
{
    AENL_SIM_GUST_FIRST_ORDER = 0, /**< one lag: exp(−|τ|/T) autocorrelation */
    AENL_SIM_GUST_DRYDEN = 1       /**< the Dryden vertical-gust filter (two lags) */
} aenl_sim_gust_t;

/** Sign of each kick of a kick train. */
typedef enum aenl_sim_kick_sign
{
    AENL_SIM_KICK_RANDOM = 0,    /**< + or − with equal chance (default) */
    AENL_SIM_KICK_ALTERNATE = 1, /**< +, −, +, ... */
    AENL_SIM_KICK_POSITIVE = 2   /**< always + */
} aenl_sim_kick_sign_t;

/** Forced excitation on one DOF ([excitation] type = sweep | multisine). */
typedef enum aenl_sim_force_kind
{
    AENL_SIM_FORCE_NONE = 0,
    AENL_SIM_FORCE_SWEEP = 1,    /**< a swept sine from force_f0 to force_f1 over the record */
    AENL_SIM_FORCE_MULTISINE = 2 /**< random-phase multisine on the grid 1/period in a band */
} aenl_sim_force_kind_t;

#define AENL_SIM_MAX_LINES 1024 /**< most frequency lines of a multisine */

/** How to run a simulation: grid, tolerances, excitation and measurement noise. */
typedef struct aenl_sim_run
{
    double duration;       /**< > 0, model time unit (τ for airfoil2dof, s for section3dof) */
    double dt;             /**< output step > 0 */
    double rtol;           /**< relative tolerance (default 1e-10) */
    double atol;           /**< absolute tolerance (default 1e-12) */
    int turbulence;        /**< 1: gust forcing on (see file comment) */
    double turb_intensity; /**< std(w_g)/U >= 0 */
    double turb_length;    /**< L: semichords (airfoil2dof) or m (section3dof) > 0 */
    uint64_t turb_seed;
    aenl_sim_gust_t turb_spectrum; /**< gust spectrum (default first order) */
    /** Kick train ([excitation] type = kicks; not with turbulence): repeated releases, like
     *  stick raps or hammer taps. At t = 0, kick_every, 2 kick_every, ... before the last sample
     *  the rate of DOF kick_dof jumps by s·r: r uniform in [kick_rate, kick_rate_max] and the
     *  sign s per kick_sign, both drawn in order from kick_seed (aenl_sim_kicks gives the
     *  sequence). kick_every must be a whole number of output steps dt. Everything else about
     *  the state carries on through a kick (aerodynamic states included). */
    int kicks;
    aenl_sim_dof_t kick_dof;
    double kick_every;    /**< > 0, model time unit */
    double kick_rate;     /**< >= 0: rad, ξ or m per model time unit */
    double kick_rate_max; /**< >= kick_rate */
    aenl_sim_kick_sign_t kick_sign;
    uint64_t kick_seed;
    /** Forced excitation (not with turbulence or kicks): a force κ·f(t) on DOF force_dof, κ its
     *  linear stiffness, so f is in the DOF's unit (rad, ξ or m: the static deflection the force
     *  would give against the DOF's own spring). Sweep: f = force_amp sin φ(t), the frequency
     *  going from force_f0 to force_f1 over the duration, linearly in time (φ = 2π (f0 t +
     *  (f1 − f0) t² / (2 T))) or, with force_log, geometrically (φ = 2π f0 (e^{k t} − 1) / k,
     *  k = ln(f1/f0) / T). Multisine: equal-amplitude sines on every frequency j / P (P =
     *  force_period, 0: the duration) in [force_f0, force_f1], phases uniform from force_seed,
     *  scaled so that the RMS over a period is force_amp. Frequencies in cycles per model time
     *  unit, below the Nyquist frequency 1 / (2 dt). The result holds f sampled (column f_<dof>).
     */
    aenl_sim_force_kind_t force;
    aenl_sim_dof_t force_dof;
    double force_amp;    /**< sweep: amplitude; multisine: RMS (> 0, DOF unit) */
    double force_f0;     /**< sweep: start; multisine: lowest frequency (> 0) */
    double force_f1;     /**< sweep: end; multisine: highest frequency (> 0) */
    int force_log;       /**< sweep: 1 geometric, 0 linear in time */
    double force_period; /**< multisine period (0: the duration) */
    uint64_t force_seed;
    double snr; /**< 0: no noise; else std(signal)/std(noise) per channel, > 0 */
    uint64_t noise_seed;
    /** Runaway bound per output channel (in the result's channel order), channel units, >= 0:
     *  the simulation stops with AENL_E_NUMERIC as soon as an accepted step leaves
     *  |y_c| <= bound[c]. 0: no bound (default). A model that runs away (a linear flutter mode,
     *  a softening spring) is then not integrated on into the stiff, huge-amplitude region where
     *  every step costs more (aenl diagnose bounds its candidates at 20 of the record's stds,
     *  or twice its largest excursion where that is further). */
    double bound[AENL_SIM_MAX_Q];
    /** Budget of accepted integration steps, per output sample, >= 0: the simulation stops
     *  with AENL_E_NUMERIC once it has taken more than this times n_samples. 0: none (default).
     *  A model that settles where it is very stiff (a softening spring's second equilibrium)
     *  can otherwise take millions of tiny steps; aenl diagnose treats it as a runaway. */
    double max_steps_per_sample;
} aenl_sim_run_t;

/** Integrator counters (aenl_sim_simulate). */
typedef struct aenl_sim_info
{
    unsigned long n_steps;    /**< accepted steps (including steps cut at an event) */
    unsigned long n_rejected; /**< rejected steps */
    unsigned long n_rhs;      /**< right-hand-side evaluations */
    unsigned long n_events;   /**< located switching events (mode changes + grazing decisions) */
    unsigned long n_grazing;  /**< events resolved as grazing (no crossing) */
    unsigned long n_stuck;    /**< hysteresis: entries into sticking */
    unsigned long n_unstick;  /**< hysteresis: exits from sticking */
} aenl_sim_info_t;

/** Sampled output: t_k = k dt, k = 0 .. n_samples-1, and the model's channels. */
typedef struct aenl_sim_result
{
    size_t n_samples;
    size_t n_channels;    /**< 2 (alpha, xi) or 3 (h, alpha, beta) */
    const char *names[4]; /**< "t" then the channel names (static strings) */
    double *t;            /**< n_samples */
    double *y;            /**< channel c, sample k: y[c * n_samples + k] */
    double *u;            /**< n_samples: the forced excitation f (noise-free), or NULL */
    const char *u_name;   /**< its column name (f_pitch, f_plunge, f_flap), or NULL */
    aenl_sim_info_t info;
} aenl_sim_result_t;

/** One mode of the linear system at one velocity (aenl_sim_modes). */
typedef struct aenl_sim_mode
{
    double re, im;    /**< eigenvalue, per model time unit */
    double damping;   /**< ζ = −re/|λ| */
    double frequency; /**< ω/ω_α (airfoil2dof) or Hz (section3dof) */
} aenl_sim_mode_t;

/** Result of a flutter search (aenl_sim_flutter). */
typedef struct aenl_sim_flutter
{
    int found;        /**< 0: no instability in [v_min, v_max] */
    double speed;     /**< U* (airfoil2dof) or m/s (section3dof) */
    double frequency; /**< ω/ω_α (airfoil2dof) or Hz (section3dof); 0 for a divergence */
} aenl_sim_flutter_t;

/* ---- models ------------------------------------------------------------------------------- */

/**
 * @brief Defaults: airfoil2dof gets the classic case (μ 100, a_h −0.5, x_α 0.25, r_α 0.5, ω̄ 0.2,
 *        ζ 0; linear flutter at U* 6.285) at U* 5.5 with the start-up terms on; section3dof
 *        Conner's parameters (linear flutter at 23.897 m/s) at 15 m/s. All laws linear, zero
 *        initial state. Cannot fail.
 */
void aenl_sim_model_default(aenl_sim_model_t *model, aenl_sim_type_t type);

/** @brief Run defaults: duration 0 (must be set), dt 0 (must be set), rtol 1e-10, atol 1e-12,
 *         no turbulence (length_scale default per type), no noise. */
void aenl_sim_run_default(aenl_sim_run_t *run, aenl_sim_type_t type);

/**
 * @brief Switching points of a law: the distinct positions where it changes slope, ascending
 *        (freeplay: the gap [α_f, α_f + δ]; hysteresis: the kinks of both branches, α_f and
 *        α_f + δ rising, −α_f − δ and −α_f falling, 3 of them when α_f = 0).
 * @return their count (0 for linear and polynomial laws), at most 4.
 */
size_t aenl_sim_law_switch_points(const aenl_sim_law_t *law, double p[4]);

/** @brief The model's velocity (U* or m/s). */
double aenl_sim_velocity(const aenl_sim_model_t *model);

/** @brief Set the model's velocity (U* or m/s). */
void aenl_sim_set_velocity(aenl_sim_model_t *model, double velocity);

/**
 * @brief Check parameters (finite, positive masses/radii/velocity, δ >= 0, polynomial sizes, no
 *        flap law on airfoil2dof) and, when run is not NULL, the run settings.
 * @return AENL_OK or AENL_E_ARG with a message naming the parameter.
 */
aenl_status_t aenl_sim_validate(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                aenl_err_t *err);

/**
 * @brief Evaluate a restoring law on its default branch (hysteresis: the branch of direction
 *        `dir` = +1 increasing, −1 decreasing). For plotting and tests. NaN if law is NULL.
 */
double aenl_sim_law_eval(const aenl_sim_law_t *law, double x, int dir);

/* ---- INI ---------------------------------------------------------------------------------- */

/**
 * @brief Load a model INI (docs/simulate.md, "The model INI"). Keys, per section (angles:
 *        `_deg` suffix = degrees, no suffix = radians; required keys marked *):
 *  - [model] type* = airfoil2dof | section3dof.
 *    airfoil2dof: ustar*, mu, a_h, x_alpha, r_alpha, omega_bar, zeta_alpha, zeta_xi (defaults:
 *    the classic case of aenl_sim_model_default()), ic_forcing = true|false (start-up terms f, g;
 *    default true). section3dof: velocity* (m/s), b, a, c, m, m_t, x_alpha, x_beta, r_alpha,
 *    r_beta, omega_h, omega_alpha, omega_beta, zeta_h, zeta_alpha, zeta_beta, rho (defaults:
 *    Conner's).
 *  - [pitch] [plunge] [flap] (flap: section3dof only): law* = linear | polynomial | freeplay |
 *    hysteresis; freeplay/hysteresis: delta[_deg]* (full gap width), alpha_f[_deg] (gap start),
 *    preload[_deg] (M0), inner_stiffness (M_f); polynomial: coeffs* = c1, c2, ... (R = Σ c_k x^k).
 *    [plunge] takes no _deg keys (ξ for airfoil2dof, metres for section3dof).
 *  - [initial] airfoil2dof: alpha[_deg], xi; section3dof: h, alpha[_deg], beta[_deg]; each also
 *    as <name>_dot[_deg] (rate per model time unit). Default 0. estimate = true | false
 *    (aenl_sim_initial_t; not given: AENL_SIM_INITIAL_AUTO).
 *  - [excitation] type = none | turbulence | kicks | sweep | multisine. turbulence:
 *    intensity (std(w_g)/U, >= 0), length_scale (L: semichords or m), spectrum = first_order |
 *    dryden (first_order), seed. kicks: dof* = pitch | plunge | flap, every* (model time unit, a
 *    whole number of dt), rate[_deg]* (the rate jump, per model time unit; plunge: no _deg),
 *    rate_max[_deg] (= rate), sign = random | alternate | positive (random), seed. sweep: dof*,
 *    amplitude[_deg]*, f_start*, f_end*, law = linear | log (linear). multisine: dof*,
 *    rms[_deg]*, f_min*, f_max*, period (the duration), seed (1).
 *  - [run] duration*, dt* (model time unit), rtol (1e-10), atol (1e-12).
 *  - [noise] snr* (> 0, std(signal)/std(noise) per channel), seed (42).
 *  Unknown sections or keys, a key given twice, a missing required key, a non-numeric, NaN or
 *  infinite value and out-of-range values (duration <= 0, dt <= 0, ...) are errors whose
 *  message is "<path>:<line>: ..." naming the key.
 *  run may be NULL: the model alone is read ([run], [excitation], [noise] are still checked when
 *  present, but duration and dt are not required), as for flutter analysis.
 * @return AENL_OK, AENL_E_IO (cannot open), AENL_E_ARG (bad content), AENL_E_DIM (memory).
 */
aenl_status_t aenl_sim_load_ini(const char *path, aenl_sim_model_t *model, aenl_sim_run_t *run,
                                aenl_err_t *err);

/**
 * @brief Write a model and run as an INI of the contract above (angles and gaps in radians,
 *        17 significant digits, linear laws omitted): aenl_sim_load_ini reads it back to the same
 *        model and run. The caller owns fp and may write comment lines before it.
 */
void aenl_sim_write_ini(FILE *fp, const aenl_sim_model_t *model, const aenl_sim_run_t *run);

/* ---- simulation --------------------------------------------------------------------------- */

/**
 * @brief Simulate with the event-located Dormand-Prince integrator (see the file comment), then
 *        add the measurement noise if run->snr > 0.
 * @param[out] res  filled on success (free with aenl_sim_result_free); zeroed on failure
 * @return AENL_OK; AENL_E_ARG bad model/run; AENL_E_NUMERIC step size underflow, non-finite
 *         state or event chatter (message gives the time).
 * @note O(steps · n_x²) time, O(n_samples) memory.
 */
aenl_status_t aenl_sim_simulate(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                aenl_sim_result_t *res, aenl_err_t *err);

/**
 * @brief Naive fixed-step classical RK4 for cross-checks and the benchmark: the branch of every
 *        law is chosen from the state at every stage (hysteresis direction from the sign of the
 *        velocity, no sticking), no event location. The step is h rounded down so that it divides
 *        dt. Turbulence and noise are applied as in aenl_sim_simulate.
 */
aenl_status_t aenl_sim_simulate_rk4(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                    double h, aenl_sim_result_t *res, aenl_err_t *err);

/**
 * @brief The gust velocity over intensity and U, w_g/(intensity U), at the output instants
 *        t_k = k dt, k = 0 .. n-1, for time constant T = L/U (model time unit): the sequence the
 *        integrators drive the model with for run's turb_seed, turb_spectrum and dt (the filter's
 *        exact discretisation under the held input). Its stationary variance is 1.
 * @return AENL_OK; AENL_E_ARG for NULL w, n = 0, or dt or T not finite and > 0.
 */
aenl_status_t aenl_sim_gust_series(const aenl_sim_run_t *run, double T, size_t n, double *w,
                                   aenl_err_t *err);

/**
 * @brief The kick train's rate jumps in order (the first at t = 0), as both integrators apply
 *        them: dv[j] for j = 0 .. n-1.
 * @return AENL_OK; AENL_E_ARG for NULL arguments or a run without kicks.
 */
aenl_status_t aenl_sim_kicks(const aenl_sim_run_t *run, size_t n, double *dv, aenl_err_t *err);

/**
 * @brief The forced excitation f at t_k = k dt, k = 0 .. n-1 (the series the integrators apply).
 * @return AENL_OK; AENL_E_ARG for NULL arguments, a run without forced excitation, or a
 *         signal aenl_sim_validate would refuse (amplitude, frequencies, lines; the DOF and the
 *         other excitations are not looked at here).
 */
aenl_status_t aenl_sim_force_series(const aenl_sim_run_t *run, size_t n, double *f,
                                    aenl_err_t *err);

/** @brief Release a result and zero it. Safe on a zeroed result. */
void aenl_sim_result_free(aenl_sim_result_t *res);

/* ---- linear analysis (LAPACKE dgeev) ------------------------------------------------------ */

/**
 * @brief The linear state matrix at `velocity` with each law replaced by R(x) = slope[dof]·x
 *        (slope NULL: 1 for every DOF; polynomial laws use coeffs[0] unless slope is given),
 *        without start-up forcing and gust states. Row-major n×n into A (capacity
 *        AENL_SIM_MAX_X²), n into *n. State order: q, q̇, aero states; q = (ξ, α) for
 *        airfoil2dof, (h, α, β) for section3dof. Time unit: τ or s.
 */
aenl_status_t aenl_sim_state_matrix(const aenl_sim_model_t *model, double velocity,
                                    const double *slope, double *A, size_t *n, aenl_err_t *err);

/**
 * @brief Oscillatory modes (Im λ > 0) at `velocity`, sorted by frequency; *n_modes <= cap.
 */
aenl_status_t aenl_sim_modes(const aenl_sim_model_t *model, double velocity, const double *slope,
                             aenl_sim_mode_t *modes, size_t cap, size_t *n_modes, aenl_err_t *err);

/**
 * @brief Lowest velocity in [v_min, v_max] where an eigenvalue crosses into Re λ > 0: scan with
 *        n_scan equal steps, then bisection to 1e-13 relative. Zero eigenvalues (|λ| below 1e-9,
 *        e.g. a DOF with zero total stiffness) are neutral and ignored.
 *        v_min, v_max <= 0 select the defaults: 0.05..50 (U*) or 0.5..200 m/s.
 */
aenl_status_t aenl_sim_flutter(const aenl_sim_model_t *model, const double *slope, double v_min,
                               double v_max, aenl_sim_flutter_t *out, aenl_err_t *err);

/**
 * @brief Outer and inner slopes of every law for the linearised flutter analysis: outer = 1 for
 *        freeplay/hysteresis/linear, coeffs[0] for polynomial; inner = inner_stiffness for
 *        freeplay and hysteresis, else the outer slope.
 * @return 1 when some DOF has a distinct inner slope (two flutter speeds to report), else 0.
 */
int aenl_sim_slopes(const aenl_sim_model_t *model, double outer[AENL_SIM_N_DOF],
                    double inner[AENL_SIM_N_DOF]);

/* ---- output ------------------------------------------------------------------------------ */

/**
 * @brief Write a result as CSV (header `t,<channels>`, "%.17g"): to `path` atomically (the file
 *        appears only when complete), or to stdout when path is NULL or "-".
 * @return AENL_OK or AENL_E_IO with a message.
 */
aenl_status_t aenl_sim_result_write_csv(const aenl_sim_result_t *res, const char *path,
                                        aenl_err_t *err);

#endif /* AENL_TOOLS_SIM_H */
