#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Build the libFuzzer targets of tests/fuzz with clang (-fsanitize=fuzzer,address,undefined, leak
# detection on) in their own build folder, and run each for a bounded time from a COPY of its
# committed seed corpus (tests/fuzz/corpus/<target>: never modified). Fails on any crash, hang
# (> 5 s per input), leak, UB report, out-of-memory (> 2 GB) or property violation (the targets
# abort()). Crash inputs are kept under BUILD/artifacts/ and named in the output.
# Usage: run_fuzz.sh [BUILD_DIR]   (default build/fuzz)
# Environment: AENL_FUZZ_SECONDS (default 10) per target; AENL_FUZZ_JOBS targets run at once
# (default: the number of cores).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build/fuzz}
secs=${AENL_FUZZ_SECONDS:-10}
jobs=${AENL_FUZZ_JOBS:-$(nproc)}
fuzz="$root/tests/fuzz"

mkdir -p "$build"
blog="$build/build.log"
CC=clang cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAENL_FUZZ=ON \
  -DAENL_BUILD_TESTS=OFF -DAENL_WERROR=OFF >"$blog" 2>&1 || { cat "$blog"; exit 1; }
# target:corpus:dictionary
specs=(fuzz_csv:csv:csv.dict fuzz_ini:ini:ini.dict fuzz_moments_f32:moments: fuzz_moments_f64:moments:
  fuzz_skf_f32:skf: fuzz_skf_f64:skf: fuzz_classifier_f32:classifier: fuzz_classifier_f64:classifier:)
targets=()
for s in "${specs[@]}"; do targets+=("${s%%:*}"); done
# Project sources are built with fewer warnings here (clang's set differs from gcc's; the strict
# build checks them); the fuzz targets themselves use -Wall -Wextra -Werror.
cmake --build "$build" -j"$(nproc)" --target "${targets[@]}" >>"$blog" 2>&1 || { cat "$blog"; exit 1; }

run_one() { # target corpus dict
  local t=$1 c=$2 d=$3 work="$build/run/$1"
  rm -rf "$work"
  mkdir -p "$work/corpus" "$build/artifacts"
  cp "$fuzz/corpus/$c/"* "$work/corpus/"
  local extra=()
  [[ -n $d ]] && extra+=("-dict=$fuzz/$d")
  # TMPDIR: the CSV/INI targets write each input to a file there (RAM when /dev/shm is usable).
  local tmp="$work"
  [[ -d /dev/shm && -w /dev/shm ]] && tmp=$(mktemp -d /dev/shm/aenl_fuzz.XXXXXX)
  local rc=0
  (cd "$work" && TMPDIR="$tmp" \
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:symbolize=1 \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/tests/fuzz/$t" -max_total_time="$secs" -timeout=5 -rss_limit_mb=2048 -max_len=4096 \
    -detect_leaks=1 -print_final_stats=1 -artifact_prefix="$build/artifacts/$t-" \
    "${extra[@]}" "$work/corpus" >"$work/log.txt" 2>&1) || rc=$?
  if [[ $tmp != "$work" ]]; then rm -rf "$tmp"; fi
  return "$rc"
}

pids=()
for s in "${specs[@]}"; do
  IFS=: read -r t c d <<<"$s"
  while (($(jobs -rp | wc -l) >= jobs)); do sleep 0.5; done
  run_one "$t" "$c" "$d" &
  pids+=("$!")
done

fail=0
i=0
for s in "${specs[@]}"; do
  IFS=: read -r t c d <<<"$s"
  if wait "${pids[$i]}"; then rc=0; else rc=$?; fi
  i=$((i + 1))
  log="$build/run/$t/log.txt"
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -Eo 'cov: [0-9]+' "$log" | tail -1 || true)
  corpus=$(ls "$build/run/$t/corpus" | wc -l)
  if ((rc == 0)); then
    printf 'fuzz %-17s ok: %s executions in %s s, %s, corpus %s inputs\n' "$t" "${execs:-?}" \
      "$secs" "${cov:-cov: ?}" "$corpus"
  else
    printf 'fuzz %-17s FAILED (exit %d) after %s executions; log %s\n' "$t" "$rc" "${execs:-?}" "$log"
    grep -E 'ERROR|fuzz_[a-z]+: |runtime error|SUMMARY|Test unit written' "$log" | head -20 || true
    fail=1
  fi
done
exit "$fail"
