/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_test_sanitized.h
 * @brief The one way a host test leaves a long end-to-end run to the plain build.
 *
 * Under ASan and UBSan (AENL_TEST_SANITIZED, set by tests/CMakeLists.txt) every pipeline runs
 * end to end once and every unit test runs; a further run of the same pipeline walks the same
 * code, costs minutes there, and is checked in full by the plain build. AENL_PLAIN_BUILD_ONLY
 * marks such a run as ignored (with the reason) in the sanitizer build and does nothing in the
 * plain build. AENL_TEST_IS_SANITIZED (1 or 0) is for a test that runs part of its work there.
 */
#ifndef AENL_TEST_SANITIZED_H
#define AENL_TEST_SANITIZED_H

#include "unity.h"

#ifdef AENL_TEST_SANITIZED
#define AENL_TEST_IS_SANITIZED     1
#define AENL_PLAIN_BUILD_ONLY(why) TEST_IGNORE_MESSAGE(why)
#else
#define AENL_TEST_IS_SANITIZED     0
#define AENL_PLAIN_BUILD_ONLY(why) ((void)0)
#endif

#endif
