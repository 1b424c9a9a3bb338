#!/bin/sh
# tests/scripts/silo_edge_bracket.sh - the two floor edges of the orifice
# bracket one discharge rate, and the bracket closes as the cell (issue 13
# item 4; docs/convergence.md section 38). The axisymmetric silo of
# examples/papers/wieckowski1999_silo_discharge (circular orifice D = 0.3
# m, fill one full width, quadratic B-splines, the Perzyna fill of section
# 37, the rate over 10-25 % of the fill) on D/6 and D/12, once with the
# floor holding the node on the orifice's edge (--edge-node held: the
# held node's zero velocity reaches into the opening, the rate converges
# from below) and once with the floor starting a cell beyond it
# (--edge-node open: the opening one cell wider in the floor's points,
# the rate converges from above). Asserts on each grid held < open, and
# that the gap open - held shrinks by at least a factor 0.75 from D/6 to
# D/12: two discretisations of one orifice whose difference is O(h) and
# vanishes with it (measured 83.84 -> 56.03 kg/s, ratio 0.668; then 30.24
# and 14.90 on D/24 and D/48, ratios 0.540 and 0.493: first order). A
# leak through the floor, or an open rule that widened the orifice by
# more than the grid's O(h), would keep the gap. About 20 s of one core.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
. "$(dirname "$0")/slow_case.sh" # skip if slow is excluded; $scratch
for cell in 0.05 0.025; do
  for edge in held open; do
    ./examples/papers/wieckowski1999_silo_discharge --geometry axisym \
      --method bspline2 --cell "$cell" --fill 1 --window-end 0.25 \
      --fluidity 30 --reference-stress 1795 --edge-node "$edge" \
      --out '' --quiet >"$scratch/out" 2>&1 || true
    rate=$(sed -n 's/^RESULT flow_rate_kg_s=\([^ ]*\) .*/\1/p' "$scratch/out")
    if [ -z "$rate" ]; then
      cat "$scratch/out"
      echo "FAIL: no rate for cell $cell m, --edge-node $edge"
      exit 1
    fi
    echo "$cell $edge $rate" >>"$scratch/rates"
  done
done
awk '
  { w[$1, $2] = $3; printf "cell %s m, edge node %s: %s kg/s\n", $1, $2, $3 }
  END {
    coarse = w["0.05", "open"] - w["0.05", "held"]
    fine = w["0.025", "open"] - w["0.025", "held"]
    printf "gap open - held: %.2f -> %.2f kg/s, ratio %.3f (at most 0.75)\n",
      coarse, fine, fine / coarse
    exit !(coarse > 0 && fine > 0 && fine <= 0.75 * coarse)
  }' "$scratch/rates"
