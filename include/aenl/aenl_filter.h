/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_filter.h
 * @brief Streaming Butterworth low-pass pre-filter (cascade of second-order sections).
 *
 * Measurement noise in flight and wind-tunnel records is broadband while the structural response
 * is narrowband (a limit cycle and its harmonics, or a few lightly damped modes). A low-pass at a
 * few times the highest frequency of interest removes most of the noise power before the
 * conditional moments are estimated, where it would otherwise blur every kink (errors in the
 * conditioning variable). A linear filter maps a linear system's response to a linear system's
 * response, so it cannot create the nonlinear signatures the classifier looks for.
 *
 * Design: digital Butterworth of even order N by the bilinear transform with pre-warping,
 * |H(e^{jw})|^2 = 1 / (1 + (tan(w/2) / tan(pi fc))^(2N)), realised as N/2 biquads in transposed
 * direct form II. The first sample primes every section to its steady state for a constant
 * input, so a record that starts at rest has no transient; one that starts in motion settles
 * within about 4 / cutoff samples, which a caller estimating statistics should leave out.
 *
 * Memory: caller-owned state, no allocation. Threading: none; re-entrant per instance.
 */
#ifndef AENL_FILTER_H
#define AENL_FILTER_H

#include "aenl/aenl_types.h"

/** Configuration, copied by aenl_filter_init(). */
typedef struct aenl_filter_cfg
{
    aenl_real_t cutoff; /**< -3 dB frequency as a fraction of the sample rate, in (0, 0.5) */
    uint16_t order;     /**< even, 2 .. 2 * AENL_FILTER_MAX_SECTIONS */
} aenl_filter_cfg_t;

/** Filter state. Caller-owned; fields are read-only for the caller. */
typedef struct aenl_filter
{
    aenl_filter_cfg_t cfg;
    uint16_t n_sections;
    uint8_t primed;                           /**< 0 until the first finite sample */
    uint32_t n_missing;                       /**< NaN/Inf samples received (saturating) */
    aenl_real_t b0[AENL_FILTER_MAX_SECTIONS]; /**< numerator (b1 = 2 b0, b2 = b0) */
    aenl_real_t a1[AENL_FILTER_MAX_SECTIONS]; /**< denominator, a0 = 1 */
    aenl_real_t a2[AENL_FILTER_MAX_SECTIONS];
    aenl_real_t z1[AENL_FILTER_MAX_SECTIONS]; /**< section states */
    aenl_real_t z2[AENL_FILTER_MAX_SECTIONS];
} aenl_filter_t;

/**
 * @brief Design the filter and clear its state.
 * @return AENL_OK; AENL_E_ARG for NULL, a cutoff outside (0, 0.5) or not finite, an odd or zero
 *         order; AENL_E_DIM for an order above 2 * AENL_FILTER_MAX_SECTIONS. On error *f is not
 *         written.
 * @note O(order), uses cos and tan once per section; no allocation.
 */
aenl_status_t aenl_filter_init(aenl_filter_t *f, const aenl_filter_cfg_t *cfg);

/** @brief Clear the state (the next sample primes it again); keep the design. NULL is ignored. */
void aenl_filter_reset(aenl_filter_t *f);

/**
 * @brief Filter one sample.
 * @param[out] out  the filtered sample; for a NaN/Inf input it is that input (a gap stays a gap)
 * @return AENL_OK; AENL_E_ARG for NULL (nothing changed); AENL_E_NUMERIC for a NaN/Inf input:
 *         the state is kept as it was (the filter holds through the gap) and n_missing counts it.
 * @note O(order): 5 multiplies and 4 adds per section; no allocation, stack < 32 B.
 */
aenl_status_t aenl_filter_push(aenl_filter_t *f, aenl_real_t in, aenl_real_t *out);

#endif /* AENL_FILTER_H */
