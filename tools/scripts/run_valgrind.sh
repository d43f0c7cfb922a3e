#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Valgrind memcheck of every `aenl` subcommand over small example inputs, success and error paths:
# any invalid read/write, use of uninitialised memory, or definite/indirect leak fails (valgrind
# exit code 3). gnuplot is a child process and is not traced. Skipped: `demo` (minutes under
# valgrind; its pieces are covered one by one here) and `bench` (timing only).
# Usage: run_valgrind.sh [AENL_BINARY]   (default build/strict/tools/aenl)
# Environment: AENL_VALGRIND_JOBS runs at once (default: the number of cores, at most 4: each
# memcheck run holds several times the command's memory).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
aenl=${1:-$root/build/strict/tools/aenl}
[[ -x $aenl ]] || { echo "run_valgrind.sh: no aenl binary at $aenl (build first)" >&2; exit 1; }
aenl=$(cd "$(dirname "$aenl")" && pwd)/$(basename "$aenl")
command -v valgrind >/dev/null || { echo "run_valgrind.sh: valgrind not installed" >&2; exit 1; }
work=$(mktemp -d "${TMPDIR:-/tmp}/aenl_valgrind.XXXXXX")
# on any exit the runs still going are stopped before their folder goes
trap 'kill $(jobs -p) 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"' EXIT
cd "$work"

n_run=0
fail=0
cores=$(nproc)
jobs=${AENL_VALGRIND_JOBS:-$((cores < 4 ? cores : 4))}
[[ $jobs =~ ^[1-9][0-9]*$ ]] || { echo "run_valgrind.sh: AENL_VALGRIND_JOBS must be a positive integer" >&2; exit 1; }
pending=()
declare -A pid_of=()
# vg EXPECTED_EXIT LABEL ARGS...: run `aenl ARGS` under memcheck in the background (at most $jobs
# at once, each with its own output and log files); exit 3 is a memcheck error. vg_sync waits for
# the pending runs and reports each in the order given; a run that reads what an earlier one
# writes comes after a vg_sync. vg_detach takes the last run out of the pending ones: it goes on
# beside the runs that follow (and their syncs), and vg_attach gives it back to be waited for.
vg() {
  local want=$1 label=$2 id=$n_run
  shift 2
  n_run=$((n_run + 1))
  while (($(jobs -rp | wc -l) >= jobs)); do wait -n || true; done
  printf '%s\t%s\n' "$want" "$label" >"$work/r$id.what"
  (
    rc=0
    valgrind -q --error-exitcode=3 --leak-check=full --errors-for-leak-kinds=definite,indirect \
      --show-leak-kinds=definite,indirect --trace-children=no --log-file="$work/r$id.vg" \
      "$aenl" "$@" >"$work/r$id.out" 2>"$work/r$id.err" || rc=$?
    echo "$rc" >"$work/r$id.rc"
  ) &
  pid_of[$id]=$!
  pending+=("$id")
}
detached=()
vg_detach() {
  detached+=("${pending[-1]}")
  unset 'pending[-1]'
}
vg_attach() {
  pending+=("${detached[@]}")
  detached=()
}
vg_sync() {
  local id want label rc
  for id in "${pending[@]}"; do
    wait "${pid_of[$id]}" 2>/dev/null || true # its status is in its .rc file
  done
  for id in "${pending[@]}"; do
    IFS=$'\t' read -r want label <"$work/r$id.what"
    rc=$(cat "$work/r$id.rc")
    if ((rc == 3)) || [[ -s $work/r$id.vg ]]; then
      printf 'valgrind %-40s MEMCHECK ERRORS (exit %d)\n' "$label" "$rc"
      sed 's/^/  /' "$work/r$id.vg" | head -60
      fail=1
    elif ((rc != want)); then
      printf 'valgrind %-40s exit %d, expected %d: %s\n' "$label" "$rc" "$want" \
        "$(head -c 300 "$work/r$id.err")"
      fail=1
    else
      printf 'valgrind %-40s clean (exit %d)\n' "$label" "$rc"
    fi
  done
  pending=()
}

# diagnose: a short hidden-freeplay record (1200 samples) against the linear baseline; grid
# calibration only, a short restart, 2 replicates and the smallest summary fit keep it to a few
# hundred short simulations. Still the longest run: it starts first.
for w in truth base; do
  awk '/^[ \t]*duration[ \t]*=/ { print "duration = 599.5"; next } { print }' \
    "$root/tools/examples/diagnose_${w}_airfoil2dof.ini" >"dg_$w.ini"
done
vg 0 "simulate (diagnose record)" simulate dg_truth.ini -o dg_meas.csv
vg_sync # dg_meas.csv is read below
vg 0 "diagnose --json --out" diagnose --measured dg_meas.csv --model dg_base.ini --json \
  --refine 0 --replicates 2 --max-evals 8 --summary-records 32 --no-plots --out dg
vg_detach # the longest run by far: it starts first and goes on beside all the others

# Every example model, its [run] shortened to 40 output steps (the integrator, events, sticking,
# turbulence and noise paths all run; full durations take minutes under valgrind).
for ini in "$root"/tools/examples/*.ini; do
  name=$(basename "$ini" .ini)
  awk '
    /^[ \t]*\[/ { sec = $0; gsub(/[ \t\[\]]/, "", sec) }
    sec == "run" && /^[ \t]*dt[ \t]*=/ { split($0, a, "="); v = a[2]; sub(/;.*/, "", v); dt = v + 0 }
    { lines[++n] = $0; secs[n] = sec }
    END {
      for (i = 1; i <= n; ++i) {
        if (secs[i] == "run" && lines[i] ~ /^[ \t]*duration[ \t]*=/) print "duration = " 40 * dt
        else print lines[i]
      }
    }' "$ini" >"$name.ini"
  vg 0 "simulate $name" simulate "$name.ini" -o "$name.csv"
  vg 0 "flutter $name" flutter "$name.ini"
done
vg 0 "flutter --json --sweep" flutter validate_freeplay_u55.ini --json --sweep --points 5

# moments and plot over a simulated record (long enough for cross-validated bandwidth).
awk '/^[ \t]*duration[ \t]*=/ { print "duration = 400"; next } { print }' \
  validate_freeplay_u55.ini >long.ini
"$aenl" simulate long.ini -o long.csv >/dev/null
vg 0 "moments (cv bandwidth, split)" moments long.csv --channel alpha -o m.csv
vg 0 "moments (given h, forgetting, falling)" moments long.csv --channel alpha --bandwidth 0.002 \
  --forgetting 0.999 --direction falling --lags 1,5 --grid -0.03:0.03:17 -o m2.csv
vg 0 "moments (stdout, --no-split)" moments long.csv --channel xi --no-split
vg 0 "identify --method moments (all channels, cv, table)" identify long.csv --method moments
vg 0 "identify (--json, given h, no prefilter)" identify long.csv --json --channel alpha \
  --bandwidth 0.002 --no-prefilter
# The likelihood-based test on the record's first 2 000 samples (a minute under memcheck).
head -n 2001 long.csv >short.csv
if command -v gnuplot >/dev/null; then
  vg 0 "identify --json --plot (the test)" identify short.csv --json --plot figs_test
else
  vg 0 "identify --json (the test)" identify short.csv --json
fi
# ... with a known input and a linear control (a 2 s shaker record of one channel)
awk '/^[ \t]*duration[ \t]*=/ { print "duration = 2"; next } { print }' \
  "$root/tools/examples/section3dof_multisine.ini" >ms.ini
"$aenl" simulate ms.ini -o ms.csv >/dev/null
vg 0 "identify --method test --input --controls" identify ms.csv --method test --input f_pitch \
  --channel beta --controls 1 --json
have_gnuplot=0
command -v gnuplot >/dev/null && have_gnuplot=1
vg_sync # m.csv is read below
if ((have_gnuplot)); then
  vg 0 "identify --plot" identify long.csv --channel alpha --bandwidth 0.002 --plot figs
  vg 0 "moments --plot" moments long.csv --channel alpha -o m3.csv --plot m3.png
  vg 0 "plot moments" plot moments m.csv -o pm.png --marks 0.004,0.013
  vg 0 "plot timeseries" plot timeseries long.csv -o ts.png
fi

vg 2 "diagnose: wrong model for the record" diagnose --measured dg_meas.csv \
  --model diagnose_base_section3dof.ini
vg 2 "identify --model: wrong model for the record" identify dg_meas.csv \
  --model diagnose_base_section3dof.ini
# Error paths must not leak either.
printf 't,alpha\n0,1\n1\n' >ragged.csv
printf 't,alpha\n0,1\n1,2\n1,3\n' >reptime.csv
printf '[model]\ntype = airfoil2dof\nustar = 4\nustar = 5\n' >dupkey.ini
vg 2 "moments: missing file" moments /nonexistent.csv --channel alpha -o x.csv
vg 2 "moments: ragged row" moments ragged.csv --channel alpha -o x.csv
vg 2 "moments: repeated time" moments reptime.csv --channel alpha -o x.csv
vg 2 "moments: unknown channel" moments long.csv --channel nope -o x.csv
vg 2 "moments: unwritable output" moments long.csv --channel alpha -o /nonexistent/x.csv
vg 2 "identify: repeated time" identify reptime.csv --json
vg 2 "identify: unknown channel" identify long.csv --channel nope
vg 2 "simulate: duplicated key" simulate dupkey.ini -o x.csv
vg 2 "simulate: unwritable output" simulate validate_linear_u4.ini -o /nonexistent/x.csv
vg 2 "flutter: unknown option" flutter validate_linear_u4.ini --bogus
if ((have_gnuplot)); then
  vg 2 "plot: not a moments CSV" plot moments long.csv -o x.png
  vg 2 "plot: unwritable output" plot timeseries long.csv -o /nonexistent/x.png
fi
vg 2 "unknown subcommand" bogus

# fit: a few EM iterations on the simulated record (success), then its error paths.
vg 0 "fit --json -o --c-header" fit long.csv --thresholds alpha:-0.004,0.004 --states 4 \
  --iter 3 --json -o fit.ini --c-header fit.h
vg 0 "fit --bootstrap" fit long.csv --thresholds alpha:-0.004,0.004 --states 4 --iter 3 \
  --bootstrap 2 --json
vg 2 "fit: unknown threshold channel" fit long.csv --thresholds nope:0 -o x.ini
vg 2 "fit: ragged row" fit ragged.csv --thresholds alpha:0 -o x.ini
vg 2 "fit: unwritable output" fit long.csv --thresholds alpha:0 -o /nonexistent/x.ini
# demo and bench: only their argument errors (a whole run is minutes under valgrind).
vg 2 "demo: unknown argument" demo --bogus
vg 2 "demo: data folder absent" demo --data /nonexistent/data --out demo_out
vg 2 "bench: unknown benchmark" bench nothing
vg_attach
vg_sync

if ((fail)); then
  echo "valgrind: FAILED ($n_run runs)"
  exit 1
fi
echo "valgrind: $n_run runs clean (demo and bench: argument errors only, a whole run is slow)"
