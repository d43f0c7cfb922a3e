/* SPDX-License-Identifier: MIT */
/* Cross-build probe: one object per core state type, so `arm-none-eabi-nm -S` reports the state
 * sizes of the float32 MCU build exactly as firmware would declare them. Never linked. */
#include "aenl/aenl.h"

aenl_filter_t aenl_sizeof_filter;
aenl_moments_t aenl_sizeof_moments;
aenl_skf_t aenl_sizeof_skf;
aenl_classifier_t aenl_sizeof_classifier;
