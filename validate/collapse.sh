#!/bin/sh
# validate/collapse.sh - the refinement study of the planar column collapse
# (issue 13 item 4) with the setting the README recommends (the example's
# defaults: Granular quadratic B-splines, Mohr-Coulomb phi 37 deg, psi 0,
# which flows at tau/sigma_n = sin 37 = tan 31 deg, no-slip floor, FLIP,
# USL; docs/convergence.md sec 11): run-out and final height over three
# cell halvings (L0/10, L0/20, L0/40) and 1x1 to 4x4 points per cell, at
# aspect ratios 0.5, 1.3, 3 and 6, against Lube et al. (2005). Writes
# validate/results/collapse_a<a>.csv (bench/convergence/sweep.sh rows),
# validate/results/collapse.md (the tables and the checks of issue 13 item
# 4) and, with gnuplot, docs/convergence_runout.png.
#
# Sized for `make validate` on 2 cores (about 25 minutes of single runs
# measured under load; sweep.sh runs JOBS=2 at a time): L0/40 runs 2x2 at a = 0.5, 1.3 and 3 (2, 2
# and 8 minutes); 1x1-4x4 run at L0/20 for a = 1.3, 3x3 at L0/20 for
# a = 3; a = 6 runs 2x2 to L0/20 (3 minutes). CASES="a:cells:ppcs ..."
# overrides the plan.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
results=$top/validate/results
mkdir -p "$results"
export COLLAPSE=${COLLAPSE:-$top/build/examples/column_collapse}
CASES=${CASES:-"0.5:0.015,0.0075,0.00375:2 1.3:0.015,0.00375:2 1.3:0.0075:1,2,3,4 3:0.015,0.00375:2 3:0.0075:2,3 6:0.015,0.0075:2"}
for a in 0.5 1.3 3 6; do : >"$results/collapse_a$a.csv.new"; done
for case in $CASES; do
  a=${case%%:*} rest=${case#*:}
  cells=$(echo "${rest%%:*}" | tr ',' ' ') ppcs=$(echo "${rest#*:}" | tr ',' ' ')
  echo "a = $a, cells $cells, points per cell $ppcs" >&2
  sh "$top/bench/convergence/sweep.sh" "a$a" "$cells" "$ppcs" --aspect "$a" \
    >>"$results/collapse_a$a.csv.new"
done
for a in 0.5 1.3 3 6; do
  if [ -s "$results/collapse_a$a.csv.new" ]; then
    sort -t, -k3,3n -k2,2gr "$results/collapse_a$a.csv.new" >"$results/collapse_a$a.csv"
  fi
  rm -f "$results/collapse_a$a.csv.new"
done
sh "$top/validate/collapse_report.sh" "$results" >"$results/collapse.md"
cat "$results/collapse.md"
if command -v gnuplot >/dev/null; then
  (cd "$results" && gnuplot "$top/validate/collapse.gp") &&
    mv "$results/convergence_runout.png" "$top/docs/convergence_runout.png"
fi
