/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose_cases.h
 * @brief Hidden-effect cases for the diagnosis tests and `aenl bench diagnose`: a truth model
 *        with one structural effect and a baseline of the same test lacking it. Evaluation
 *        harness, not part of the host library.
 */
#ifndef AENL_DIAGNOSE_CASES_H
#define AENL_DIAGNOSE_CASES_H

#include "aenl_tools/aenl_diagnose.h"

/** One hidden-effect case: the truth model and conditions, and a baseline lacking the effect. */
typedef struct aenl_diagnose_case
{
    char name[64];
    aenl_sim_model_t truth, base;
    aenl_sim_run_t truth_run, base_run; /**< truth: its own seeds, SNR 3; base: other seeds */
    aenl_diagnose_effect_t effect;
    aenl_sim_dof_t dof;
    /** 0: the truth is measured with the event-located integrator the diagnosis simulates with;
     *  n > 0: with naive fixed-step RK4, n steps a sample (aenl_sim_simulate_rk4: no event
     *  location, hysteresis without sticking), a simulator the diagnosis does not share.
     *  aenl_diagnose_case_make() sets 0. */
    unsigned truth_rk4_steps;
} aenl_diagnose_case_t;

/** Number of built-in hidden-effect cases. */
size_t aenl_diagnose_n_cases(void);

/**
 * @brief Build case `index` with the truth's parameters and seeds drawn from `seed` (the
 *        diagnosis never sees them). `long_record` 1 gives 60 s at 1 kHz (3-DOF) or 12000
 *        samples (2-DOF) instead of the short CI records.
 * @return AENL_OK or AENL_E_ARG for an index out of range.
 */
aenl_status_t aenl_diagnose_case_make(size_t index, uint64_t seed, int long_record,
                                      aenl_diagnose_case_t *c, aenl_err_t *err);

/** Simulate a case's truth (with truth_run, and RK4 when truth_rk4_steps > 0) and return it as a
 *  measured table (t + channels). */
aenl_status_t aenl_diagnose_case_measure(const aenl_diagnose_case_t *c, aenl_table_t *out,
                                         aenl_err_t *err);

/** aenl_diagnose_bound() for a case's truth and test (truth_run: a Dryden spectrum applies,
 *  truth_rk4_steps does not), as standard deviation / |truth| in rel_sd. */
aenl_status_t aenl_diagnose_case_bound(const aenl_diagnose_case_t *c, unsigned n_rep,
                                       unsigned n_jac, double rel_sd[AENL_DIAGNOSE_MAX_PAR],
                                       size_t *n_par, aenl_err_t *err);

#endif /* AENL_DIAGNOSE_CASES_H */
