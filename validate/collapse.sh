#!/bin/sh
# validate/collapse.sh - the refinement study of the planar column collapse
# (issue 13 item 4) with the setting the README recommends (the example's
# defaults: Granular uGIMP, Mohr-Coulomb phi 35 deg, psi 0, Coulomb floor
# mu = tan phi, FLIP, USL): run-out and final height over three cell
# halvings (L0/10, L0/20, L0/40) and 2x2 / 3x3 / 4x4 points per cell, at
# aspect ratios 0.5, 1.3 and 3, against Lube et al. (2005). Writes
# validate/results/collapse_a<a>.csv (bench/convergence/sweep.sh rows),
# validate/results/collapse.md (the tables and the checks of issue 13 item
# 4) and, with gnuplot, docs/convergence_runout.png.
#
# Sized for `make validate` on 2 cores (about 20 minutes on an idle
# machine): the finest grid runs 2x2 and 3x3 at a = 1.3 and 2x2 at the
# other ratios; 4x4 runs at L0/10 and L0/20. CASES="a:cells:ppcs ..."
# overrides the plan.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
results=$top/validate/results
mkdir -p "$results"
export COLLAPSE=${COLLAPSE:-$top/build/examples/column_collapse}
CASES=${CASES:-"0.5:0.015,0.0075:2,3,4 0.5:0.00375:2 1.3:0.015,0.0075:2,3,4 1.3:0.00375:2,3 3:0.015,0.0075:2,3,4 3:0.00375:2"}
for a in 0.5 1.3 3; do : >"$results/collapse_a$a.csv.new"; done
for case in $CASES; do
  a=${case%%:*} rest=${case#*:}
  cells=$(echo "${rest%%:*}" | tr ',' ' ') ppcs=$(echo "${rest#*:}" | tr ',' ' ')
  echo "a = $a, cells $cells, points per cell $ppcs" >&2
  sh "$top/bench/convergence/sweep.sh" "a$a" "$cells" "$ppcs" --aspect "$a" \
    >>"$results/collapse_a$a.csv.new"
done
for a in 0.5 1.3 3; do
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
