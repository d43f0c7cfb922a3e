/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_config.h
 * @brief Compile-time capacities and switches of the aenl core.
 *
 * Every capacity has a default behind `#ifndef` and a range check right after it. A project can
 * set its own values with `-D`, or put them in a header named by `AENL_CONFIG_HEADER`
 * (`-DAENL_CONFIG_HEADER='"my_aenl_config.h"'`), which is included first.
 * Each line says what one unit of the capacity costs in RAM (float32 build, 4-byte reals).
 */
#ifndef AENL_CONFIG_H
#define AENL_CONFIG_H

#ifdef AENL_CONFIG_HEADER
#include AENL_CONFIG_HEADER
#endif

/* ---- numeric type ------------------------------------------------------------------------- */

/** 0: `float` (MCU build), 1: `double` (host build). Set as a PUBLIC definition by CMake. */
#ifndef AENL_USE_DOUBLE
#define AENL_USE_DOUBLE 0
#endif
#if (AENL_USE_DOUBLE != 0) && (AENL_USE_DOUBLE != 1)
#error "AENL_USE_DOUBLE must be 0 or 1"
#endif

/* ---- aenl_moments ------------------------------------------------------------------------- */

/** Most grid nodes per lag. Costs nothing by itself: storage is sized by MAX_CELLS. */
#ifndef AENL_MOMENTS_MAX_GRID
#define AENL_MOMENTS_MAX_GRID 256
#endif
#if (AENL_MOMENTS_MAX_GRID < 3) || (AENL_MOMENTS_MAX_GRID > 4096)
#error "AENL_MOMENTS_MAX_GRID must be in [3, 4096]"
#endif

/** Most lags per estimator. 2 B each. */
#ifndef AENL_MOMENTS_MAX_LAGS
#define AENL_MOMENTS_MAX_LAGS 16
#endif
#if (AENL_MOMENTS_MAX_LAGS < 1) || (AENL_MOMENTS_MAX_LAGS > 64)
#error "AENL_MOMENTS_MAX_LAGS must be in [1, 64]"
#endif

/** Largest lag in samples. History ring: 5 B per unit (one real plus one validity byte). */
#ifndef AENL_MOMENTS_MAX_LAG
#define AENL_MOMENTS_MAX_LAG 64
#endif
#if (AENL_MOMENTS_MAX_LAG < 1) || (AENL_MOMENTS_MAX_LAG > 65000)
#error "AENL_MOMENTS_MAX_LAG must be in [1, 65000]"
#endif

/**
 * 1: every running sum carries a 16-bit compensation term (the part of a sum s that float
 * rounding lost, in units of |s| 2^-38), so a float32 estimator keeps its accuracy past 2^24
 * contributions per cell (10^9 samples without forgetting; the stored sums then have about 40
 * significant bits). 0: plain Welford sums; fine in double, and in float32 with a forgetting
 * factor < 1 or fewer than ~10^7 contributions per cell. Either way the lags share their weight
 * sums (a conditioning sample pairs at every lag or at none: see aenl_moments_push).
 * Default: on for float, off for double.
 */
#ifndef AENL_MOMENTS_COMPENSATED
#if AENL_USE_DOUBLE
#define AENL_MOMENTS_COMPENSATED 0
#else
#define AENL_MOMENTS_COMPENSATED 1
#endif
#endif
#if (AENL_MOMENTS_COMPENSATED != 0) && (AENL_MOMENTS_COMPENSATED != 1)
#error "AENL_MOMENTS_COMPENSATED must be 0 or 1"
#endif

/**
 * Statistics cells: n_lags * (2 when symmetric) * n_grid * (2 with the direction split) must
 * fit. The default 384 holds the standard configuration: 64 nodes, 3 lags, direction split.
 * Storage is sized by AENL_MOMENTS_MAX_SUMS.
 */
#ifndef AENL_MOMENTS_MAX_CELLS
#define AENL_MOMENTS_MAX_CELLS 384
#endif
#if (AENL_MOMENTS_MAX_CELLS < 3) || (AENL_MOMENTS_MAX_CELLS > 1048576)
#error "AENL_MOMENTS_MAX_CELLS must be in [3, 1048576]"
#endif

/**
 * Running sums: 2 per cell (mean, M2) plus 2 per node and direction (the weight sums, shared by
 * the lags), 4 B each in float32 (6 B compensated); the default then holds MAX_CELLS cells of 3 or
 * more lag series, 2/3 of them with one lag series (one lag, not symmetric) and 8/9 with two.
 */
#ifndef AENL_MOMENTS_MAX_SUMS
#define AENL_MOMENTS_MAX_SUMS (2 * AENL_MOMENTS_MAX_CELLS + 2 * ((AENL_MOMENTS_MAX_CELLS + 2) / 3))
#endif
#if (AENL_MOMENTS_MAX_SUMS < 8) || (AENL_MOMENTS_MAX_SUMS > 4194304)
#error "AENL_MOMENTS_MAX_SUMS must be in [8, 4194304]"
#endif

/* ---- aenl_skf ----------------------------------------------------------------------------- */

/**
 * Most states. The filter state holds about (3 + 2 n_modes) n_x^2 reals: with the defaults
 * (8, 4, 4) sizeof(aenl_skf_t) is about 3.5 KiB in float32; an aenl_skf_model_t (flash) about
 * n_modes (2 n_x^2 + n_x) + n_z n_x + n_z^2 + n_x^2 + n_modes^2 reals (2.6 KiB).
 */
#ifndef AENL_SKF_MAX_X
#define AENL_SKF_MAX_X 8
#endif
#if (AENL_SKF_MAX_X < 1) || (AENL_SKF_MAX_X > 64)
#error "AENL_SKF_MAX_X must be in [1, 64]"
#endif

/** Most measured outputs. Work space: about 3 n_x + n_z reals per unit. */
#ifndef AENL_SKF_MAX_Z
#define AENL_SKF_MAX_Z 4
#endif
#if (AENL_SKF_MAX_Z < 1) || (AENL_SKF_MAX_Z > AENL_SKF_MAX_X)
#error "AENL_SKF_MAX_Z must be in [1, AENL_SKF_MAX_X]"
#endif

/** Most modes. State: 2 (n_x^2 + n_x) + 2 reals per mode (per-mode IMM estimates, double-buffered).
 */
#ifndef AENL_SKF_MAX_MODES
#define AENL_SKF_MAX_MODES 4
#endif
#if (AENL_SKF_MAX_MODES < 1) || (AENL_SKF_MAX_MODES > 16)
#error "AENL_SKF_MAX_MODES must be in [1, 16]"
#endif

/* ---- aenl_filter -------------------------------------------------------------------------- */

/** Most second-order sections of a low-pass pre-filter (order = 2 x sections). 28 B each. */
#ifndef AENL_FILTER_MAX_SECTIONS
#define AENL_FILTER_MAX_SECTIONS 4
#endif
#if (AENL_FILTER_MAX_SECTIONS < 1) || (AENL_FILTER_MAX_SECTIONS > 16)
#error "AENL_FILTER_MAX_SECTIONS must be in [1, 16]"
#endif

/* ---- assertions --------------------------------------------------------------------------- */

/** Internal invariants only (never argument checks). Override with a trap on target. */
#ifndef AENL_ASSERT
#include <assert.h>
#define AENL_ASSERT(x) assert(x)
#endif

#endif /* AENL_CONFIG_H */
