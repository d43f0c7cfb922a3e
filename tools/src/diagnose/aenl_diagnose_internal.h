/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose_internal.h
 * @brief Private helpers shared by the aenl_diagnose*.c files (not installed).
 */
#ifndef AENL_DIAGNOSE_INTERNAL_H
#define AENL_DIAGNOSE_INTERNAL_H

#include "aenl_tools/aenl_diagnose.h"

/** Largest normalised difference of one signature element (keeps a diverged run finite). */
#define AENL_DIAGNOSE_CAP 10.0

/** Smallest noise floor used as a divisor (both runs of a pair diverged: floor 0). */
#define AENL_DIAGNOSE_MIN_FLOOR 1e-3

/** Fewest effective samples for a curve node to count. */
#define AENL_DIAGNOSE_MIN_WEIGHT 10.0

/** Quantile probabilities of the amplitude family. */
extern const double aenl_diagnose_quant_p[AENL_DIAGNOSE_N_QUANT];

/** Normalised difference of element i of family f (a reference, b other), NaN where it does
 *  not count; *w receives its weight. Elements: amplitude quantiles then envelope windows;
 *  curves [dir][lag][node]; spectral bands. */
double aenl_diagnose_element(const aenl_diagnose_chan_t *c, const aenl_diagnose_sig_t *a,
                             const aenl_diagnose_sig_t *b, aenl_diagnose_family_t f, size_t i,
                             double *w);

/** Number of elements of family f. */
size_t aenl_diagnose_n_elements(const aenl_diagnose_chan_t *c, aenl_diagnose_family_t f);

/** Relative variance of the squared gaps of the pairs of n_run runs, from their sums s2 (of g^2)
 *  and s4 (of g^4) over n_pair pairs: the dispersion that sets the effective number of
 *  independent elements of a gap (for a sum of M squared normal differences, g^2 is chi-square
 *  with M degrees of freedom in units of its mean, relative variance 2 / M). Pairs that share a
 *  run are correlated (1/4 for such sums), so the spread between all n_run (n_run - 1) / 2 pairs
 *  falls short of the marginal one by their mean correlation; that is corrected (not when some
 *  pairs are missing: n_pair smaller). NAN with fewer than two pairs or no spread to measure
 *  (every run alike). */
double aenl_diagnose_rel_var(double s2, double s4, size_t n_pair, size_t n_run);

/** Output channel names of a model type ("alpha","xi" or "h","alpha","beta"); count in *n. */
const char *const *aenl_diagnose_channel_names(aenl_sim_type_t type, size_t *n);

/** 1 when the baseline's initial state is to be fitted to the record: a run without
 *  turbulence (its response is the initial state's alone, up to kicks) whose [initial] says
 *  estimate = true, or, without kicks, says nothing and gives a zero state (a baseline that
 *  would not move). */
int aenl_diagnose_initial_wanted(const aenl_sim_model_t *m, const aenl_sim_run_t *run);

/** The initial state (positions and rates of every DOF) that brings base's response closest,
 *  in least squares with each channel weighted by its residual spread, to the record y (n
 *  samples a channel, the model's channel order, chan from aenl_diagnose_chan_setup) over one
 *  period of the model's fastest mode from its start; Gauss-Newton with the simulator, from
 *  the state given (estimate = true) or from the first sample at rest. out: base with the
 *  fitted state; info: its standard errors and window. AENL_E_ARG when the window cannot be
 *  simulated or does not determine the state (message says so): out is base from the start,
 *  info says estimated with window 0 and no errors; AENL_E_DIM out of memory. */
aenl_status_t aenl_diagnose_initial_fit(const aenl_sim_model_t *base, const aenl_sim_run_t *run,
                                        const double *y, size_t n, const aenl_diagnose_chan_t *chan,
                                        aenl_sim_model_t *out, aenl_diagnose_initial_t *info,
                                        aenl_err_t *err);

#endif /* AENL_DIAGNOSE_INTERNAL_H */
