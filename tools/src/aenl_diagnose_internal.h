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

/** Output channel names of a model type ("alpha","xi" or "h","alpha","beta"); count in *n. */
const char *const *aenl_diagnose_channel_names(aenl_sim_type_t type, size_t *n);

#endif /* AENL_DIAGNOSE_INTERNAL_H */
