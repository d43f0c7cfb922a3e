#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The whole test command (the README's Quick start, second line; .ci/run calls exactly this):
#   1. install missing Debian packages;
#   2. strict build (warnings as errors, header self-check) and the full ctest suite
#      (Unity suites f32/f64, host tools, core purity);
#   3. the same suite built with AddressSanitizer + UndefinedBehaviorSanitizer;
#   3a. static analysis: everything (core, tools, tests) built with clang-tidy (.clang-tidy, every
#       finding an error) and cppcheck (--error-exitcode) run on each source (AENL_STATIC_ANALYSIS);
#   3b. libFuzzer targets (CSV reader, INI loader, aenl_moments and aenl_skf f32/f64) for a bounded
#       time each from the committed seed corpus (tools/scripts/run_fuzz.sh);
#   3c. valgrind memcheck of every CLI subcommand, success and error paths (run_valgrind.sh);
#   4. the Cortex-M4F cross build of aenl_core_f32 with the undefined-symbol allow-list and sizes,
#      its unit suites on an emulated Cortex-M4F (QEMU) and the instructions per sample there.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
jobs=$(nproc)
"$root/tools/scripts/deps.sh" all

step() { printf '\n=== %s (at %d s)\n' "$*" "$SECONDS"; }

step "strict build (-Werror) + ctest"
cmake -S "$root" -B "$root/build/strict" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAENL_WERROR=ON >/dev/null
cmake --build "$root/build/strict" -j"$jobs"
ctest --test-dir "$root/build/strict" -j"$jobs" --output-on-failure

step "ASan + UBSan build + ctest"
cmake -S "$root" -B "$root/build/asan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAENL_SANITIZE=ON >/dev/null
cmake --build "$root/build/asan" -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$root/build/asan" -j"$jobs" --output-on-failure

step "static analysis (clang-tidy + cppcheck)"
cmake -S "$root" -B "$root/build/sa" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAENL_STATIC_ANALYSIS=ON >/dev/null
cmake --build "$root/build/sa" -j"$jobs"

step "fuzz (libFuzzer; run_fuzz.sh holds the seconds per target)"
"$root/tools/scripts/run_fuzz.sh" "$root/build/fuzz"

step "valgrind memcheck of the CLI"
"$root/tools/scripts/run_valgrind.sh" "$root/build/strict/tools/aenl"

step "Cortex-M4F cross build of the core, its tests on an emulated Cortex-M4F"
"$root/tools/scripts/check_m4f.sh" "$root/build/m4f"

step "all checks passed"
