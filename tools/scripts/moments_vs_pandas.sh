#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `aenl moments` against the same estimator written with pandas and numpy
# (tools/scripts/moments_reference.py), each as a whole process from the CSV: a record of N
# samples (default 10^6) of an AR(2) process written with 17 significant digits, lags 1, 10, 30,
# 64 nodes over its 0.1 % .. 99.9 % range, bandwidth three node spacings. Runs the two in turn
# R times (default 3) and prints each run's seconds, the medians and their ratio (and the
# reference's own seconds without the interpreter's start and imports), and the largest
# difference between the two outputs (mean and its standard error relative to the record's
# standard deviation, variance relative to its variance, n_eff relative to itself); it fails
# when a difference exceeds 1e-10, or the two hold different points. Installs python3-pandas
# (Debian) when it is missing; builds aenl as the Quick start does.
# Usage: moments_vs_pandas.sh [N] [R]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
n=${1:-1000000}
runs=${2:-3}
py=/usr/bin/python3 # the interpreter Debian's python3-pandas installs into
[[ $n =~ ^[0-9]+$ && $n -ge 1000 && $runs =~ ^[0-9]+$ && $runs -ge 1 ]] || {
  echo "usage: moments_vs_pandas.sh [N >= 1000] [R >= 1]" >&2; exit 2; }
if ! $py -c 'import pandas, numpy' 2>/dev/null; then
  echo "moments_vs_pandas: installing python3-pandas" >&2
  sudo=""
  if [[ $(id -u) != 0 ]]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends python3-pandas python3-numpy >/dev/null
fi
"$root/tools/scripts/aenl" --version >/dev/null
aenl="$root/build/release/tools/aenl"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# the record, and the grid and bandwidth both are given
read -r lo hi < <($py - "$n" "$work/rec.csv" <<'PY'
import sys
import numpy as np
n, path = int(sys.argv[1]), sys.argv[2]
rng = np.random.default_rng(1)
e = rng.standard_normal(n)
x = np.zeros(n)
for k in range(2, n):  # x_k = 1.8 x_{k-1} - 0.9 x_{k-2} + e_k: a lightly damped mode
    x[k] = 1.8 * x[k - 1] - 0.9 * x[k - 2] + e[k]
np.savetxt(path, np.column_stack((0.01 * np.arange(n), x)), fmt="%.17g", delimiter=",",
           header="t,x", comments="")
print(repr(float(np.quantile(x, 0.001))), repr(float(np.quantile(x, 0.999))))
PY
)
h=$($py -c "print(repr(3.0 * ($hi - $lo) / 63.0))")
secs() { # command...: its wall seconds; a failed command stops the comparison
  local t0 t1
  t0=$(date +%s.%N)
  "$@" >/dev/null 2>"$work/err" || {
    echo "moments_vs_pandas: failed: $*" >&2; cat "$work/err" >&2; exit 1; }
  t1=$(date +%s.%N)
  $py -c "print(f'{$t1 - $t0:.3f}')"
}
a_times=() p_times=() p_inner=()
for ((r = 1; r <= runs; ++r)); do
  a_times+=("$(secs "$aenl" moments "$work/rec.csv" --channel x --lags 1,10,30 \
    --grid "$lo:$hi:64" --bandwidth "$h" -o "$work/aenl.csv")")
  p_times+=("$(secs $py "$root/tools/scripts/moments_reference.py" "$work/rec.csv" x 1,10,30 \
    "$lo" "$hi" 64 "$h" "$work/pandas.csv" "$work/inner")")
  p_inner+=("$(cat "$work/inner")")
done
$py - "$n" "$work/rec.csv" "$work/aenl.csv" "$work/pandas.csv" "${a_times[*]}" "${p_times[*]}" \
  "${p_inner[*]}" <<'PY'
import statistics, sys
import pandas as pd
n, fr, fa, fp = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
ta = [float(v) for v in sys.argv[5].split()]
tp = [float(v) for v in sys.argv[6].split()]
ti = [float(v) for v in sys.argv[7].split()]
sd = float(pd.read_csv(fr)["x"].std())
a = pd.read_csv(fa, comment="#").dropna()
p = pd.read_csv(fp)
m = a.merge(p, on=["lag", "x"], suffixes=("_a", "_p"))
if len(m) != len(a) or len(m) != len(p):
    sys.exit(f"moments_vs_pandas: the outputs hold different points ({len(a)}, {len(p)}, {len(m)} in both)")
scale = {"mean": sd, "se": sd, "var": sd * sd, "n_eff": m["n_eff_p"].abs()}
diff = {q: float(((m[q + "_a"] - m[q + "_p"]).abs() / scale[q]).max()) for q in scale}
ma, mp = statistics.median(ta), statistics.median(tp)
print(f"moments, {n} samples x lags 1,10,30 x 64 nodes, whole process from the CSV:")
print(f"  aenl moments:   {' '.join(f'{v:.3f}' for v in ta)} s (median {ma:.3f})")
print(f"  pandas + numpy: {' '.join(f'{v:.3f}' for v in tp)} s (median {mp:.3f}; of which"
      f" reading, computing and writing {statistics.median(ti):.3f})")
print(f"  ratio {mp / ma:.1f}x; the same {len(m)} (lag, node) points; largest difference: mean"
      f" {diff['mean']:.1e} sd, se {diff['se']:.1e} sd, var {diff['var']:.1e} sd^2, n_eff"
      f" {diff['n_eff']:.1e} relative")
if max(diff.values()) > 1e-10:
    sys.exit("moments_vs_pandas: the two outputs disagree")
PY
