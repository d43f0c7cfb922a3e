#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Install the Debian 12 packages aenl needs that are missing (apt-get; root or sudo). Quiet when
# everything is present. Usage: deps.sh [all|build]   (build: enough to build and run `aenl`)
set -euo pipefail
want=(cmake make gcc pkg-config liblapacke-dev libinih-dev libcjson-dev gnuplot-nox)
if [[ ${1:-all} == all ]]; then
  want+=(gcc-arm-none-eabi libnewlib-arm-none-eabi binutils-arm-none-eabi)
  want+=(clang libclang-rt-14-dev valgrind) # run_fuzz.sh (libFuzzer runtime), run_valgrind.sh
  want+=(clang-tidy cppcheck)                # test_all.sh static analysis (AENL_STATIC_ANALYSIS)
  want+=(man-db)                             # the install check reads the installed man page
  want+=(qemu-system-arm)                    # check_m4f.sh: the core's tests on an emulated M4F
fi
missing=()
for p in "${want[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
((${#missing[@]} == 0)) && exit 0
echo "aenl: installing missing Debian packages: ${missing[*]}" >&2
sudo=""
if [[ $(id -u) != 0 ]]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
