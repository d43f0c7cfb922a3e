/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_clock.h
 * @brief Host helper: a monotonic wall clock in seconds, for the benches' and the diagnosis's
 *        timings (differences only; the origin is arbitrary).
 */
#ifndef AENL_TOOLS_CLOCK_H
#define AENL_TOOLS_CLOCK_H

/** Seconds on the monotonic clock (CLOCK_MONOTONIC); only differences mean anything. */
double aenl_now_s(void);

#endif /* AENL_TOOLS_CLOCK_H */
