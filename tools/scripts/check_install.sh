#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Install gate: `cmake --install` a build into a temporary prefix, then build and run a consumer
# through find_package(aenl) and through pkg-config. Usage: check_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$src/tests/install_consumer" -B "$work/b" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/b" >/dev/null
"$work/b/consumer_f32"
"$work/b/consumer_f64"
libdir=$(ls -d "$work"/prefix/lib*/pkgconfig | head -n 1)
for prec in f32 f64; do
  flags=$(PKG_CONFIG_PATH="$libdir" pkg-config --cflags --libs "aenl_core_$prec")
  # shellcheck disable=SC2086
  cc -std=c99 "$src/tests/install_consumer/consumer.c" $flags -o "$work/pc_$prec"
  "$work/pc_$prec"
done
echo "install: find_package(aenl) and pkg-config consumers ok"
