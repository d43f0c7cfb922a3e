#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Regenerate the table of docs/ground-tests.md from `aenl identify` runs on the public benchmark
# data sets (not part of the repository; docs/real-data.md says where they come from).
# usage: tools/scripts/ground_tests.sh DATA_DIR [AENL_BINARY]  (default: build and use
#        tools/scripts/aenl)
# DATA_DIR holds one folder per data set: silverbox_benchmark, bouc_wen_benchmark,
# f16_gvt_benchmark, bristol_flutter_rig_pitch_heave, laid out as the rows below name them.
# Per record: the test with its measured input (the verdict, switching points and wall time of
# that run), 5 linear controls (how many are called nonlinear), and one linear control written
# out and identified again with its input and without it. The table is the runs' own verdict
# lines, shortened; the document is written only when every run succeeded, through a
# temporary file. It takes about half an hour on two cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
[[ $# -ge 1 && -d $1 ]] || { echo "usage: ground_tests.sh DATA_DIR [AENL_BINARY]" >&2; exit 2; }
data=$(cd "$1" && pwd)
aenl=${2:-$root/tools/scripts/aenl}
doc="$root/docs/ground-tests.md"
if [[ $(grep -c '^<!-- ground-tests:begin -->$' "$doc") != 1 ||
      $(grep -c '^<!-- ground-tests:end -->$' "$doc") != 1 ]]; then
  echo "ground_tests: $doc needs one '<!-- ground-tests:begin -->' and one" \
       "'<!-- ground-tests:end -->' line" >&2
  exit 1
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# verdict FILE: the run's verdict line, shortened ("polynomial (hardening) in acc2, 1.000")
verdict() {
  awk '/^verdict: / {
         sub(/^verdict: /, "");
         extra = "";
         if (match($0, /\), (hardening|softening)$/)) { extra = substr($0, RSTART + 3); }
         cls = $1; ch = "";
         if ($2 == "in") { ch = $3; }
         conf = "";
         if (match($0, /confidence [0-9.]+/)) { conf = substr($0, RSTART + 11, RLENGTH - 11); }
         out = cls;
         if (extra != "") { out = out " (" extra ")"; }
         if (ch != "") { out = out " in " ch; }
         print out ", " conf;
       }' "$1"
}
# points FILE: the named law's switching points, or a dash
points() {
  awk '/^switching points/ {
         sub(/^[^:]*: /, ""); n = split($0, p, /\], /); s = "";
         for (i = 1; i <= n; ++i) { split(p[i], q, " "); s = s (i > 1 ? ", " : "") q[1]; }
         print s; found = 1 }
       END { if (!found) print "–" }' "$1"
}
# identify_to OUT ARGS...: aenl identify ARGS into OUT; a failure stops the script
identify_to() {
  local out=$1
  shift
  "$aenl" identify "$@" >"$out" 2>"$work/err" || {
    echo "ground_tests: failed: identify $*" >&2; cat "$work/err" >&2; exit 1; }
}
# row LABEL FILE INPUTS ("-": none)
row() {
  local label=$1 f=$data/$2 inp=$3
  local in_args=()
  [[ $inp != - ]] && in_args=(--input "$inp")
  local t0 t1
  t0=$(date +%s.%N)
  identify_to "$work/rec.txt" "$f" "${in_args[@]}"
  t1=$(date +%s.%N)
  local called given alone="–"
  rm -f "$work/ctl.csv"
  if "$aenl" identify "$f" "${in_args[@]}" --controls 5 --write-control "$work/ctl.csv" \
    >"$work/ctl_run.txt" 2>"$work/err"; then
    called=$(sed -n 's/.*called nonlinear: \([0-9]* of [0-9]*\)$/\1/p' "$work/ctl_run.txt")
    [[ -n $called ]] || called="none could be fitted"
    identify_to "$work/ctl_in.txt" "$work/ctl.csv" "${in_args[@]}"
    given=$(verdict "$work/ctl_in.txt")
    if [[ $inp != - ]]; then
      identify_to "$work/ctl_alone.txt" "$work/ctl.csv"
      alone=$(verdict "$work/ctl_alone.txt")
    fi
  elif grep -q 'is unstable (largest pole modulus' "$work/err"; then
    # the fitted linear model has a pole outside the unit circle: no control can be simulated
    called="none: $(sed -n 's/.*(largest pole modulus \([^)]*\)).*/model unstable, pole \1/p' "$work/err")"
    given="–"
    alone="–"
  else
    echo "ground_tests: failed: identify $f --controls" >&2; cat "$work/err" >&2; exit 1
  fi
  printf '| %s | %s | %s | %s | %.0f s | %s | %s | %s |\n' "$label" "$inp" \
    "$(verdict "$work/rec.txt")" "$(points "$work/rec.txt")" \
    "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')" "$called" "$given" "$alone"
}

sb=silverbox_benchmark; bw=bouc_wen_benchmark; f16=f16_gvt_benchmark
br=bristol_flutter_rig_pitch_heave
{
  echo "| record | input | verdict, confidence | switching points | time | linear controls called nonlinear | a linear control, input given | the same, no --input (the input a channel too) |"
  echo "|---|---|---|---|---|---|---|---|"
  row "Silverbox SNLS80mV, 610 Hz" $sb/SNLS80mV.csv V1_input_V
  row "Silverbox multilevel 5 mV, 2441 Hz" $sb/noel2013_multilevel/SNJP_level005.csv u_input_V
  row "Silverbox multilevel 150 mV, 2441 Hz" $sb/noel2013_multilevel/SNJP_level150.csv u_input_V
  row "Bouc–Wen multisine" $bw/BoucWen_test_multisine.csv u_force_N
  row "Bouc–Wen sine sweep" $bw/BoucWen_test_sinesweep.csv u_force_N
  row "F-16 multisine, level 1" $f16/F16Data_FullMSine_Level1.csv force_N,voltage_V
  row "F-16 sine sweep, level 1" $f16/F16Data_SineSw_Level1.csv force_N,voltage_V
  row "F-16 multisine, level 7" $f16/F16Data_FullMSine_Level7.csv force_N,voltage_V
  row "F-16 sine sweep, level 7" $f16/F16Data_SineSw_Level7.csv force_N,voltage_V
  row "Bristol rig, LCO at 25 m/s" $br/lco_sweep_17092018/17092018_CBC_V250_TowardsHB.csv -
} >"$work/table.md"

version=$("$aenl" --version | awk '{print $2}')
stamp="(aenl $version, $(date -u +%Y-%m-%d), $(nproc) processors, $(uname -m); generated by \`tools/scripts/ground_tests.sh\`)"
awk -v table="$work/table.md" -v stamp="$stamp" '
  /^<!-- ground-tests:begin -->$/ { print; while ((getline l < table) > 0) print l; print ""; print stamp; skip = 1; next }
  /^<!-- ground-tests:end -->$/ { skip = 0 }
  !skip' "$doc" >"$work/doc.md"
mv "$work/doc.md" "$doc"
echo "ground_tests: $doc written" >&2
