/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_impulse.h
 * @brief Screening of impulsive excitation (kicks, raps, a release's start) out of a record
 *        before a regression that assumes free motion.
 *
 * The input is, row by row, each channel's equation residual (aenl_rfs_residual): what the
 * free-law model of the motion leaves unexplained. An impulse J at time t0, seen through the
 * pre-filter h, adds J h[n - t0] to it. The statistic is the residual summed over the last
 * `window` rows, s[n]: the impulse's pulse sums to J (the filter passes a constant unchanged),
 * while measurement noise reaches the residual through a second difference, whose sum
 * telescopes to a difference of two first differences and does not grow with the window. So
 * an impulse too small to see in any single row stands out of s.
 *
 * Two passes over the residuals:
 * 1. aenl_impulse_scan() for every row: the distribution of |s| per channel. aenl_impulse_arm()
 *    then sets each channel's threshold at z robust standard deviations (median |s| / 0.6745;
 *    impulses are rare, so the median sees the free motion) and says whether the record is
 *    impulsive: more rows beyond it than a Gaussian tail gives. The threshold weighs two unequal
 * costs: a false alarm leaves a few rows of free motion out, a missed impulse stays in the
 * regression as a force the law may take up. So z is a per-row level (3: 0.27 % of Gaussian rows),
 * not a record-wide maximum.
 * 2. aenl_impulse_step() for every row, with that row's data: returns the data rows in order,
 *    held back (by about two spans), each with whether it is left out. A run of rows where
 *    some channel's |s| exceeds its threshold (gaps up to a window joined) is a candidate when
 *    it lasts at most 3 windows, as the pulse entering and leaving the window does; a longer
 *    run is the model's own error, sustained where the motion is large. A candidate is an
 *    impulse when it puts energy into the motion: the mean square of the standardised data
 *    over `span` rows from its start exceeds `gain` times that over the `span` rows before it.
 *    (A misfit of the model, at a freeplay contact say, also makes short runs, but leaves the
 *    energy as it was.) Around an impulse, the rows from `before` ahead of the run's start (s
 *    rises within a window of the impulse) to `after` past it are left out.
 *    aenl_impulse_drain() returns the rows still held at the end.
 */
#ifndef AENL_TOOLS_IMPULSE_H
#define AENL_TOOLS_IMPULSE_H

#include <stddef.h>

#include "aenl/aenl.h"
#include "aenl_tools/aenl_io.h"

#define AENL_IMPULSE_MAX_CH 8

typedef struct aenl_impulse_cfg
{
    size_t n_ch;   /**< 1..AENL_IMPULSE_MAX_CH */
    size_t window; /**< rows summed, >= 1: at least the pre-filter's impulse response */
    size_t before; /**< rows left out before an impulse's first exceedance, >= window */
    size_t after;  /**< rows left out after it (the pre-filter's response) */
    double z;      /**< threshold in robust standard deviations of the sum, > 0 */
    size_t span;   /**< rows over which the motion's energy is compared (a period), >= 1 */
    double gain;   /**< energy ratio an impulse must bring, >= 1 */
    double center[AENL_IMPULSE_MAX_CH]; /**< standardisation of the data rows, */
    double scale[AENL_IMPULSE_MAX_CH];  /**< (x - center) / scale, scale > 0 */
} aenl_impulse_cfg_t;

typedef struct aenl_impulse aenl_impulse_t;

/** @return AENL_OK; AENL_E_ARG (message in err) for a bad configuration; AENL_E_IO out of
 *  memory. */
aenl_status_t aenl_impulse_create(aenl_impulse_t **out, const aenl_impulse_cfg_t *cfg,
                                  aenl_err_t *err);

/** Pass 1: one row of residuals (n_ch values; NaN where none was formed: the sums restart). */
void aenl_impulse_scan(aenl_impulse_t *s, const double *e);

/** End of pass 1: set the thresholds and restart for pass 2. Returns 1 when the record is
 *  impulsive: in some channel, more rows of pass 1 exceed the threshold than the Gaussian tail
 *  at z gives, by 3 standard errors (the sums taken as rows / window independent draws); 0
 *  when there is nothing to screen (Gaussian forcing, measurement noise). */
int aenl_impulse_arm(aenl_impulse_t *s);

/**
 * @brief Pass 2: one row of residuals e and the data row it came with (n_ch values each).
 * @return 1 when out (n_ch values) holds the next data row in order (before + 4 window + 1
 *         rows back) and *left_out says whether it is left out, 0 while the delay fills.
 */
int aenl_impulse_step(aenl_impulse_t *s, const double *e, const double *row, double *out,
                      int *left_out);

/** After pass 2: 1 while out and *left_out receive a row still held back (in order), then 0. */
int aenl_impulse_drain(aenl_impulse_t *s, double *out, int *left_out);

/** Events found in pass 2, and rows left out. */
size_t aenl_impulse_events(const aenl_impulse_t *s);
size_t aenl_impulse_left_out(const aenl_impulse_t *s);

/** After pass 2: 1 when the motion is a train of free decays: its energy over consecutive
 *  spans falls more often than it rises, by 3 standard errors of a fair coin. Under stationary
 *  forcing (turbulence) it rises as often as it falls. */
int aenl_impulse_decaying(const aenl_impulse_t *s);

/** Threshold of channel ch's sum (after aenl_impulse_arm). */
double aenl_impulse_threshold(const aenl_impulse_t *s, size_t ch);

void aenl_impulse_free(aenl_impulse_t *s);

#endif /* AENL_TOOLS_IMPULSE_H */
