/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sim_internal.h
 * @brief Private to the aenl_sim*.c files: the assembled linear structure of a model and its
 *        per-DOF branch state ("mode").
 *
 * Every model is written in one generic second-order form (q the structural DOFs, z the
 * aerodynamic lag states, g the gust angle w_g/U):
 *
 *     M q̈ = −C q̇ − K q − κ∘R(q) + Ez z + Eg g + fvec φ(t)
 *     ż   = Zq q + Zqd q̇ + diag(Zz) z + Zg g
 *     ġ   = (−g + u(t)) / T_g                               (turbulence, first order)
 *
 * or, for the Dryden spectrum, g = √3 g1 + (1 − √3) g2 with T_g ġ1 = −g1 + u, T_g ġ2 = −g2 + g1,
 * with state x = [q, q̇, z, g] or [q, q̇, z, g1, g2] and φ(t) = Σ_i f_amp[i] exp(−f_rate[i] t) (the
 * airfoil2dof start-up terms f, g of the Wagner integrals).
 */
#ifndef AENL_SIM_INTERNAL_H
#define AENL_SIM_INTERNAL_H

#include "aenl_tools/aenl_rng.h"
#include "aenl_tools/aenl_sim.h"

/* R. T. Jones's (1940) approximation of the Wagner function,
 * φ(τ) = 1 − ψ1 exp(−ε1 τ) − ψ2 exp(−ε2 τ). */
#define SIM_PSI1 0.165
#define SIM_PSI2 0.335
#define SIM_EPS1 0.0455
#define SIM_EPS2 0.3
/* sqrt(3), the lead of the Dryden vertical-gust filter (1 + sqrt(3) T s) */
#define SIM_SQRT3 1.7320508075688772

typedef struct sim_sys
{
    aenl_sim_type_t type;
    int nq, nz, nx;
    /* gust filter states at the end of x: 0, 1 (x[nx-1] is the gust angle) or 2 (Dryden) */
    int gust;
    int dof[AENL_SIM_MAX_Q];            /* law slot (aenl_sim_dof_t) of each q */
    aenl_sim_law_t law[AENL_SIM_MAX_Q]; /* law of each q */
    double M[AENL_SIM_MAX_Q][AENL_SIM_MAX_Q];
    double Minv[AENL_SIM_MAX_Q][AENL_SIM_MAX_Q];
    double C[AENL_SIM_MAX_Q][AENL_SIM_MAX_Q];
    double K[AENL_SIM_MAX_Q][AENL_SIM_MAX_Q];
    double Ez[AENL_SIM_MAX_Q][AENL_SIM_MAX_Z];
    double Eg[AENL_SIM_MAX_Q];
    double Zq[AENL_SIM_MAX_Z][AENL_SIM_MAX_Q];
    double Zqd[AENL_SIM_MAX_Z][AENL_SIM_MAX_Q];
    double Zz[AENL_SIM_MAX_Z];
    double Zg[AENL_SIM_MAX_Z];
    double kappa[AENL_SIM_MAX_Q];
    double fvec[AENL_SIM_MAX_Q];
    double f_amp[2], f_rate[2];
    int forcing;
    double gust_T;             /* gust filter time constant, model time unit */
    double freq_scale;         /* Im λ times this = reported frequency (ω/ω_α or Hz) */
    int out_q[AENL_SIM_MAX_Q]; /* output channel c is q index out_q[c] */
    int n_out;
    const struct sim_force *force; /* forced excitation, or NULL */
    int force_q;                   /* the forced DOF's q index */
} sim_sys_t;

/* A forced excitation ready to evaluate (sim_force_init). */
typedef struct sim_force
{
    aenl_sim_force_kind_t kind;
    double amp, f0, f1, T;
    int log;
    size_t n_lines;
    double w[AENL_SIM_MAX_LINES];  /* angular frequencies of the multisine */
    double ph[AENL_SIM_MAX_LINES]; /* their phases */
} sim_force_t;

/* Check the run's forced excitation and prepare it (the model says which DOFs exist). */
aenl_status_t sim_force_check(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                              aenl_err_t *err);
void sim_force_init(sim_force_t *f, const aenl_sim_run_t *run);
double sim_force_eval(const sim_force_t *f, double t);
/* Attach f to sys (NULL or kind none: no forcing). */
void sim_force_attach(sim_sys_t *sys, const sim_force_t *f, const aenl_sim_run_t *run);
/* The column name of a DOF's force (f_pitch, f_plunge, f_flap). */
const char *sim_force_name(aenl_sim_dof_t dof);

/* Branch of one DOF's law. */
typedef struct sim_branch
{
    int region; /* 0 below the gap, 1 inside, 2 above (freeplay/hysteresis) */
    int dir;    /* hysteresis direction +1 / −1 */
    int stuck;  /* hysteresis sticking (Filippov sliding) */
} sim_branch_t;

typedef struct sim_mode
{
    sim_branch_t b[AENL_SIM_MAX_Q];
} sim_mode_t;

/** Lag states of a gust spectrum's filter: 1 first order, 2 Dryden. */
/* The kick train's generator: sim_kick_next gives the rate jumps in order. */
typedef struct sim_kick_gen
{
    aenl_rng_t rng;
    double lo, hi;
    aenl_sim_kick_sign_t sign;
    size_t j;
} sim_kick_gen_t;

void sim_kick_init(sim_kick_gen_t *g, const aenl_sim_run_t *run);
double sim_kick_next(sim_kick_gen_t *g);

/* Output steps between kicks (0: no kicks; run validated). */
size_t sim_kick_steps(const aenl_sim_run_t *run);

int sim_gust_order(aenl_sim_gust_t spectrum);

/** Gust filter states a run needs: 0 without turbulence, else sim_gust_order. */
int sim_gust_states(const aenl_sim_run_t *run);

/** Assemble the generic form at `velocity` with n_gust gust filter states (sim_gust_states). */
aenl_status_t sim_sys_build(const aenl_sim_model_t *model, double velocity, int n_gust,
                            double gust_length, sim_sys_t *sys, aenl_err_t *err);

/** The Dryden filter's output from its two lag states: sqrt(3) z1 + (1 - sqrt(3)) z2. */
double sim_dryden_output(double z1, double z2);

/** The gust angle g of state x (0 without turbulence). */
double sim_gust_angle(const sim_sys_t *sys, const double *x);

/** Gap boundaries of law on the branch of direction dir. */
void sim_law_bounds(const aenl_sim_law_t *law, int dir, double *lo, double *hi);

/** Region of x for law on branch dir; on a boundary, moving_up (+1/−1/0) breaks the tie. */
int sim_law_region(const aenl_sim_law_t *law, int dir, double x, int moving_up);

/** Value of the law on the branch (region, dir) extended smoothly to any x. */
double sim_law_branch(const aenl_sim_law_t *law, int region, int dir, double x);

/**
 * Right-hand side in `mode`. u is the gust input. When rreq is not NULL, rreq[i] receives, for
 * each stuck q i, the restoring value R that holds it (between the two branches), else 0.
 * linear != 0: every law replaced by slope[i]·q_i and φ(t) = 0 (state matrix).
 */
void sim_rhs(const sim_sys_t *sys, const sim_mode_t *mode, double t, const double *x, double u,
             double *dx, double *rreq);

/** Same, with laws replaced by R = slope[q]·q and no forcing (for the state matrix). */
void sim_rhs_linear(const sim_sys_t *sys, const double *slope_q, const double *x, double *dx);

#endif /* AENL_SIM_INTERNAL_H */
