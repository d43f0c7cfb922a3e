#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Cortex-M4F gate: cross-build aenl_core_f32 with arm-none-eabi-gcc,
# then (1) every undefined symbol must be on the allow-list (float libm, mem*, integer EABI helpers:
# no heap, no stdio, no double-precision helper), (2) print arm-none-eabi-size of the core
# (budget: 16 384 B of text in all),
# (3) print the state sizes (budget: aenl_moments_t <= 8 192 B in the default configuration) and
# (4) the largest stack frames from -fstack-usage (limit 768 B),
# (5) run the core's float32 unit tests on an emulated Cortex-M4F (QEMU) and (6) print the
# instructions per sample of the streaming calls there.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build/m4f}
cmake -S "$root" -B "$build" -DCMAKE_TOOLCHAIN_FILE="$root/tools/cmake/arm-none-eabi.cmake" \
      -DCMAKE_BUILD_TYPE=Release -DAENL_BUILD_TESTS=OFF -DAENL_BUILD_TOOLS=OFF \
      -DAENL_M4F_TESTS=ON -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >/dev/null
cmake --build "$build" --target aenl_core_f32 -j2 >/dev/null
# The sizes below are those of -Os: every compile of the core must say so, and nothing later on
# its command line may override it.
cc_lines=$(grep -E '"command": .*aenl_core_f32' "$build/compile_commands.json" || true)
if [[ -z $cc_lines ]] || echo "$cc_lines" | grep -vqE -- '-Os( -DNDEBUG)?( |")' ||
   echo "$cc_lines" | grep -qE -- '-O[0-3g]( |")'; then
  echo "m4f: FAIL: the core is not compiled with -Os alone:"; echo "$cc_lines" | head -n 2; exit 1
fi
echo "m4f: every compile of the core uses -Os"
lib=$(find "$build" -name 'libaenl_core_f32.a' | head -n 1)

allowed='^(expf|sqrtf|logf|fabsf|floorf|ceilf|cosf|tanf|memset|memcpy|memmove|__aeabi_mem(set|clr|cpy|move)[48]?|__aeabi_u?idiv(mod)?|__aeabi_u?ldivmod|__aeabi_l(asr|lsl|lsr|mul|cmp)|__aeabi_ulcmp)$'
# Calls between the library's own objects are not external: drop symbols the archive defines.
defined=$(arm-none-eabi-nm --defined-only "$lib" | awk 'NF==3{print $3}' | sort -u)
undef=$(arm-none-eabi-nm -u "$lib" | awk 'NF==2{print $2}' | sort -u | comm -23 - <(echo "$defined"))
bad=$(echo "$undef" | grep -vE "$allowed" | grep -v '^$' || true)
echo "m4f: undefined symbols of the core: $(echo $undef)"
if [[ -n $bad ]]; then
  echo "m4f: FAIL: symbols outside the allow-list (heap, stdio or double precision?): $(echo $bad)"
  exit 1
fi
echo "m4f: allow-list ok"
echo "m4f: arm-none-eabi-size of the core (float32, -Os):"
arm-none-eabi-size -t "$lib"
text_budget=16384
text=$(arm-none-eabi-size -t "$lib" | awk '/\(TOTALS\)/ {print $1}')
if [[ -z $text ]] || ((text > text_budget)); then
  echo "m4f: FAIL: the core's text is ${text:-unknown} B (budget $text_budget B)"; exit 1
fi
echo "m4f: core text $text B (budget $text_budget B)"

probe="$build/m4f_sizeof.o"
arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -std=c99 -Os \
  -I"$root/include" -c "$root/tools/scripts/m4f_sizeof.c" -o "$probe"
echo "m4f: state sizes (float32, default aenl_config.h):"
arm-none-eabi-nm -S "$probe" | while read -r _addr size _kind name; do
  [[ $name == aenl_sizeof_* ]] && echo "  sizeof(aenl_${name#aenl_sizeof_}_t) = $((16#$size)) B"
done
moments_budget=8192
moments=$(arm-none-eabi-nm -S "$probe" | awk '$4 == "aenl_sizeof_moments" {print $2}')
if [[ -z $moments ]] || (((16#$moments) > moments_budget)); then
  echo "m4f: FAIL: sizeof(aenl_moments_t) is $((16#${moments:-0})) B in the standard configuration" \
       "(budget $moments_budget B)"
  exit 1
fi
echo "m4f: sizeof(aenl_moments_t) $((16#$moments)) B (budget $moments_budget B)"

arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -std=c99 -Os \
  -DAENL_MOMENTS_COMPENSATED=0 -I"$root/include" -c "$root/tools/scripts/m4f_sizeof.c" -o "$probe"
echo "m4f: the same with AENL_MOMENTS_COMPENSATED=0 (plain Welford cells):"
arm-none-eabi-nm -S "$probe" | while read -r _addr size _kind name; do
  [[ $name == aenl_sizeof_* ]] && echo "  sizeof(aenl_${name#aenl_sizeof_}_t) = $((16#$size)) B"
done

sufiles=$(find "$build" -name '*.su' -path '*aenl_core_f32*')
echo "m4f: largest stack frames (-fstack-usage):"
cat $sufiles | sort -t$'\t' -k2,2nr | head -n 8 | sed 's/^/  /'
worst=$(cat $sufiles | awk -F'\t' '{if ($2+0 > m) m = $2+0} END {print m+0}')
if grep -h -E 'dynamic' $sufiles >/dev/null 2>&1; then
  echo "m4f: FAIL: a function has dynamic stack usage (VLA or alloca)"; exit 1
fi
if ((worst > 768)); then
  echo "m4f: FAIL: a function uses $worst B of stack (limit 768)"; exit 1
fi
echo "m4f: worst frame $worst B"

# The core's float32 unit tests on an emulated Cortex-M4F (QEMU mps2-an386, semihosting console),
# built with the same flags as the core; then the harness's known-failure suite must fail there
# too, and the instructions per sample of the streaming calls are printed.
command -v qemu-system-arm >/dev/null || {
  echo "m4f: FAIL: qemu-system-arm not installed (Debian package qemu-system-arm; deps.sh all)"; exit 1; }
cmake --build "$build" --target aenl_m4f_tests -j2 >/dev/null
qemu() { # ELF [extra qemu options...]: run it, its console on stdout; the exit status is its own
  local elf=$1
  shift
  timeout 600 qemu-system-arm -M mps2-an386 -cpu cortex-m4 -nographic -monitor none -serial none \
    -semihosting-config enable=on,target=native "$@" -kernel "$elf"
}
for elf in "$build"/tests/m4f/test_*_m4f.elf; do
  name=$(basename "$elf" .elf)
  rc=0
  out=$(qemu "$elf" 2>&1) || rc=$?
  # a crash, a hang or a suite that ran nothing prints no such line: each is a failure
  summary=$(echo "$out" | grep -E '^[1-9][0-9]* Tests 0 Failures [0-9]+ Ignored' | tail -n 1 || true)
  if ((rc != 0)) || [[ -z $summary || $(echo "$out" | tail -n 1) != OK* ]]; then
    echo "m4f: FAIL: $name on the emulated Cortex-M4F (exit $rc):"; echo "$out" | tail -n 30; exit 1
  fi
  echo "m4f: $name on the emulated Cortex-M4F: $summary"
done
rc=0
out=$(qemu "$build/tests/m4f/selftest_fail_m4f.elf" 2>&1) || rc=$?
if ((rc != 3)) || ! echo "$out" | grep -q '^5 Tests 3 Failures 1 Ignored'; then
  echo "m4f: FAIL: a failing test is not reported through the emulator (exit $rc)"; exit 1
fi
echo "m4f: the harness's known failures are reported through the emulator (exit 3)"
qemu "$build/tests/m4f/m4f_cost.elf" -icount shift=0
echo "m4f: ok"
