#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Install gate: `cmake --install` a build (stripped) into a temporary prefix, then build and run a
# consumer through find_package(aenl) and through pkg-config. With "tools": the prefix is then
# moved and the installed aenl run from there; it must find its own files beside itself
# (BIN/../share/aenl) and name no path of the source or build tree.
# Usage: check_install.sh BUILD_DIR SOURCE_DIR [tools]
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" --strip >/dev/null
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
[[ ${3:-} == tools ]] || exit 0

mv "$work/prefix" "$work/moved"
bin="$work/moved/bin/aenl"
share="$work/moved/share/aenl"
for tree in "$src" "$build"; do
  if strings -a "$bin" | grep -F -q "$tree"; then
    echo "the installed aenl names $tree:" >&2
    strings -a "$bin" | grep -F "$tree" >&2
    exit 1
  fi
done
run() { (cd "$work" && env -u AENL_SHARE_DIR -u AENL_PLOT_DIR "$bin" "$@"); }
run --version
run simulate "$share/examples/paper_polynomial_pitch.ini" -o rec.csv
test -s "$work/rec.csv"
if command -v gnuplot >/dev/null; then
  run plot timeseries rec.csv -o rec.png >/dev/null
  test -s "$work/rec.png"
fi
# completion: the subcommand, then its options, as the installed binary lists them
PATH="$work/moved/bin:$PATH" bash -c '
  source "$1"
  COMP_WORDS=(aenl ide); COMP_CWORD=1; _aenl; [[ ${COMPREPLY[*]} == identify ]]
  COMP_WORDS=(aenl identify --me); COMP_CWORD=2; _aenl; [[ ${COMPREPLY[*]} == --method ]]
' _ "$share/../bash-completion/completions/aenl"
if command -v man >/dev/null; then
  man -l "$work/moved/share/man/man1/aenl.1" 2>/dev/null | grep -q "find the structural nonlinearity"
fi
echo "install: the moved tree runs (examples, plot scripts, completion, man page)"
