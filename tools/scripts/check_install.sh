#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Install gate: `cmake --install` a build (stripped) into a temporary prefix, then build and run a
# consumer through find_package(aenl) and through pkg-config. With "tools": the prefix is then
# moved and the installed aenl run from there; it must find its own files beside itself
# (BIN/../share/aenl) and name no path of the source or build tree. `aenl demo` (about two
# minutes) runs there too, in a folder of its own and with an environment that names neither
# tree; where strace works, no file access of it or of its children may name one.
# The source tree stays where it is: the build folder is often inside it, and ctest runs other
# tests from there at the same time.
# Usage: check_install.sh BUILD_DIR SOURCE_DIR [tools]
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
work=$(mktemp -d)
case "$work/" in # the runs below must be outside both trees
  "$src"/* | "$build"/*) rmdir "$work" && work=$(mktemp -d -p /tmp) ;;
esac
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
for exe in "$work"/moved/bin/*; do # aenl and the helpers its benches run
  for tree in "$src" "$build"; do
    if strings -a "$exe" | grep -F -q "$tree"; then
      echo "the installed $(basename "$exe") names $tree:" >&2
      strings -a "$exe" | grep -F "$tree" >&2
      exit 1
    fi
  done
done
# PATH without the trees (gnuplot and man are looked up there); nothing else is passed on.
clean_path=$(tr ':' '\n' <<<"$PATH" | { grep -v -F -e "$src" -e "$build" || true; } | paste -s -d ':' -)
# LD_LIBRARY_PATH stays when set: an install may link libraries from outside the system's folders
keep_env=()
[[ -n ${LD_LIBRARY_PATH:-} ]] && keep_env+=(LD_LIBRARY_PATH="$LD_LIBRARY_PATH")
run() { (cd "$work" && env -i PATH="$clean_path" HOME="$work" LC_ALL=C "${keep_env[@]}" "$bin" "$@"); }
run --version
run bench stream 100000 --plain >/dev/null
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
echo "install: the moved tree runs (examples, plot scripts, stream bench, completion, man page)"

# The demo: every worked example end to end from the installed files alone.
trace=()
if command -v strace >/dev/null && strace -f -o /dev/null true 2>/dev/null; then
  trace=(strace -f -q -e trace=file -o "$work/demo.trace")
  strace --seccomp-bpf -f -o /dev/null true 2>/dev/null && trace+=(--seccomp-bpf)
fi
(cd "$work" && env -i PATH="$clean_path" HOME="$work" LC_ALL=C "${keep_env[@]}" "${trace[@]}" \
  "$bin" demo --out "$work/demo" >"$work/demo.log" 2>&1) || {
  echo "the installed aenl demo failed:" >&2
  cat "$work/demo.log" >&2
  exit 1
}
demo_fail() {
  echo "the installed aenl demo $1:" >&2
  cat "$work/demo.log" >&2
  exit 1
}
grep -F -x -q "demo done: $work/demo" "$work/demo.log" || demo_fail "did not report its end"
for f in paper_polynomial_pitch paper_hysteresis_pitch paper_flap_freeplay two_freeplays; do
  test -s "$work/demo/$f.csv" || demo_fail "wrote no $f.csv"
done
if command -v gnuplot >/dev/null; then
  ls "$work"/demo/*_identify/*.png >/dev/null 2>&1 || demo_fail "drew no identify figure"
fi
if ((${#trace[@]})); then
  for tree in "$src" "$build"; do
    if grep -F -q -e "\"$tree/" -e "\"$tree\"" "$work/demo.trace"; then
      echo "the installed aenl demo reached into $tree:" >&2
      grep -F -e "\"$tree/" -e "\"$tree\"" "$work/demo.trace" | head -n 20 >&2
      exit 1
    fi
  done
fi
echo "install: the installed demo runs without the source and build trees"
