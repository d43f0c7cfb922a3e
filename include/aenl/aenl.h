/* SPDX-License-Identifier: MIT */
/**
 * @file aenl.h
 * @brief Umbrella header of the aenl core: streaming kernel conditional moments (and, as they land,
 *        the incremental classifier and the switching Kalman filter).
 *
 * The core is C99 and uses only <stdint.h>, <stddef.h>, <string.h>, <math.h> and <assert.h>: no
 * heap, no stdio, no clocks, no mutable globals. Every state is caller-owned and sized at compile
 * time (aenl_config.h). The scalar is float (AENL_USE_DOUBLE=0, the MCU build) or double (host).
 */
#ifndef AENL_H
#define AENL_H

#include "aenl/aenl_config.h"
#include "aenl/aenl_types.h"
#include "aenl/aenl_filter.h"
#include "aenl/aenl_moments.h"
#include "aenl/aenl_skf.h"
#include "aenl/aenl_classifier.h"

#endif /* AENL_H */
