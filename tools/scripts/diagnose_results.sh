#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Regenerate the hidden-effect results in docs/diagnose.md from `aenl bench diagnose` output.
# usage: tools/scripts/diagnose_results.sh [AENL_BINARY]   (default: build and use tools/scripts/aenl)
# Two blocks, each the bench's own lines copied verbatim (nothing in them is edited by hand):
#   diagnose-bench:   the whole matrix, truth seeds 101 and 102 (--seeds 2);
#   diagnose-variants: for the truth measured by another simulator (--rk4, --dryden, both), each
#                      run's summary line and the lines of its cases that miss a goal or whose
#                      summary fit is rejected.
# The file is written only when every bench run succeeded, through a temporary file.
# It takes about 10 minutes on two cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
aenl=${1:-$root/tools/scripts/aenl}
doc="$root/docs/diagnose.md"
for tag in diagnose-bench diagnose-variants; do
  if [[ $(grep -c "^<!-- $tag:begin -->\$" "$doc") != 1 ||
        $(grep -c "^<!-- $tag:end -->\$" "$doc") != 1 ]]; then
    echo "diagnose_results: docs/diagnose.md needs one '<!-- $tag:begin -->' and one" \
         "'<!-- $tag:end -->' line" >&2
    exit 1
  fi
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# run NAME ARGS...: the bench's output into $work/NAME.txt; it must end with its summary line
run() {
  local name=$1
  shift
  echo "diagnose_results: aenl bench diagnose --seeds 2 $* ..." >&2
  "$aenl" bench diagnose --seeds 2 "$@" >"$work/$name.txt"
  if ! grep -qE '^summary: [0-9]+ cases; ' "$work/$name.txt"; then
    echo "diagnose_results: bench diagnose $* printed no summary line; nothing written" >&2
    exit 1
  fi
}
run own
run rk4 --rk4
run dryden --dryden
run both --rk4 --dryden
version=$("$aenl" --version | awk '{print $2}')
stamp="aenl $version, $(date -u +%Y-%m-%d), $(nproc) processors, $(uname -m)"

{
  echo '```'
  sed 's/ *$//' "$work/own.txt"
  echo '```'
  echo "(\`aenl bench diagnose --seeds 2\`; $stamp)"
} >"$work/bench.md"
{
  for v in rk4:--rk4 dryden:--dryden both:'--rk4 --dryden'; do
    name=${v%%:*}
    echo "\`aenl bench diagnose --seeds 2 ${v#*:}\`:"
    echo '```'
    grep -E '^summary: ' "$work/$name.txt"
    grep -E '(MISS|FAIL|rejected)' "$work/$name.txt" | sed 's/ *$//' || true
    echo '```'
  done
  echo "($stamp)"
} >"$work/variants.md"

# replace TAG FILE: the lines between TAG's markers in the doc by FILE's
replace() {
  awk -v tag="$1" -v file="$2" '
    $0 == "<!-- " tag ":begin -->" {print; while ((getline line < file) > 0) print line; skip = 1; next}
    $0 == "<!-- " tag ":end -->" {skip = 0}
    !skip' "$3"
}
replace diagnose-bench "$work/bench.md" "$doc" >"$work/doc1.md"
replace diagnose-variants "$work/variants.md" "$work/doc1.md" >"$work/doc2.md"
cp "$work/doc2.md" "$doc.tmp"
mv "$doc.tmp" "$doc"
echo "diagnose_results: docs/diagnose.md written" >&2
