#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Core purity gate: the embeddable core (include/aenl, src) must not use the heap, stdio, stdlib
# or LAPACK, and includes only <stdint.h> <stddef.h> <string.h> <math.h> <assert.h>.
set -u
root=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$root" || exit 2
fail=0
hits=$(grep -rnE '\b(malloc|calloc|realloc|free|printf|fprintf|sprintf|snprintf|puts|fopen|exit|abort)\s*\(|\bFILE\b|lapacke|LAPACKE' \
       --include='*.c' --include='*.h' include/aenl src || true)
if [[ -n $hits ]]; then
  echo "core purity: forbidden call or type in the core:"; echo "$hits"; fail=1
fi
bad_inc=$(grep -rnE '^\s*#\s*include\s*<' --include='*.c' --include='*.h' include/aenl src \
          | grep -vE '<(stdint|stddef|string|math|assert)\.h>' || true)
if [[ -n $bad_inc ]]; then
  echo "core purity: system header outside <stdint.h> <stddef.h> <string.h> <math.h> <assert.h>:"
  echo "$bad_inc"; fail=1
fi
# Code only: comments are stripped first (they may well name the maths they implement).
dbl=$(for f in src/*.c; do
        gcc -fpreprocessed -dD -E -P "$f" 2>/dev/null | grep -nE '\b(sqrt|exp|log|fabs|floor|ceil|pow|sin|cos|tan)\s*\(' \
          | grep -vE 'aenl_(sqrt|exp|log|fabs|floor|ceil|cos|tan)' | sed "s|^|$f: |"
      done)
if [[ -n $dbl ]]; then
  echo "core purity: direct libm call in a core source (use the aenl_ wrappers):"; echo "$dbl"; fail=1
fi
if ((fail == 0)); then
  echo "core purity: ok ($(ls include/aenl/*.h src/*.[ch] | wc -l) files)"
fi
exit $fail
